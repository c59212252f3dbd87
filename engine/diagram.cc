#include "engine/diagram.h"

#include <stdexcept>

#include <fmt/format.h>

namespace mb {

int Diagram::FindBlock(const std::string& block_name) const {
  const auto it = block_index_.find(block_name);
  return it == block_index_.end() ? -1 : it->second;
}

SignalRef Diagram::ResolveSignal(const std::string& signal) const {
  for (std::size_t k = 0; k < inputs_.size(); ++k) {
    if (inputs_[k].name == signal) return SignalRef{-1, static_cast<int>(k)};
  }
  for (const auto& out : outputs_) {
    if (out.name == signal) return out.source;
  }
  const auto dot = signal.rfind('.');
  const std::string block_name = dot == std::string::npos ? signal : signal.substr(0, dot);
  const int b = FindBlock(block_name);
  if (b < 0) {
    throw std::invalid_argument(fmt::format(
        "signal '{}': no element '{}' (write signals as element.port, e.g. plant.x)", signal, block_name));
  }
  const Block& block = *blocks_[static_cast<std::size_t>(b)];
  if (dot == std::string::npos) {
    if (block.output_ports().empty()) {
      throw std::invalid_argument(fmt::format("signal '{}': element '{}' has no outputs", signal, block_name));
    }
    return SignalRef{b, 0};
  }
  const int port = block.FindOutputPort(signal.substr(dot + 1));
  if (port < 0) {
    std::string ports;
    for (const auto& p : block.output_ports()) ports += (ports.empty() ? "" : ", ") + p.name;
    throw std::invalid_argument(fmt::format("signal '{}': element '{}' has no output '{}'; its outputs: {}", signal,
                                            block_name, signal.substr(dot + 1), ports.empty() ? "(none)" : ports));
  }
  return SignalRef{b, port};
}

int Diagram::SignalWidth(const SignalRef& ref) const {
  if (ref.is_external()) return 1;
  return blocks_[static_cast<std::size_t>(ref.block)]->output_ports()[static_cast<std::size_t>(ref.port)].width;
}

std::string Diagram::SignalName(const SignalRef& ref) const {
  if (ref.is_external()) return inputs_[static_cast<std::size_t>(ref.port)].name;
  const Block& b = *blocks_[static_cast<std::size_t>(ref.block)];
  return b.name() + "." + b.output_ports()[static_cast<std::size_t>(ref.port)].name;
}

}  // namespace mb
