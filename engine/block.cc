#include "engine/block.h"

#include <stdexcept>

#include <fmt/format.h>

namespace mb {

int Block::DeclareInputPort(std::string port_name, int width, std::string unit, bool direct_feedthrough) {
  if (width < 1) throw std::invalid_argument(fmt::format("block '{}': port '{}' width must be >= 1", name_, port_name));
  inputs_.push_back(PortSpec{std::move(port_name), width, std::move(unit), direct_feedthrough});
  return static_cast<int>(inputs_.size()) - 1;
}

int Block::DeclareOutputPort(std::string port_name, int width, std::string unit) {
  if (width < 1) throw std::invalid_argument(fmt::format("block '{}': port '{}' width must be >= 1", name_, port_name));
  outputs_.push_back(PortSpec{std::move(port_name), width, std::move(unit), false});
  return static_cast<int>(outputs_.size()) - 1;
}

int Block::FindInputPort(const std::string& port_name) const {
  for (std::size_t i = 0; i < inputs_.size(); ++i) {
    if (inputs_[i].name == port_name) return static_cast<int>(i);
  }
  return -1;
}

int Block::FindOutputPort(const std::string& port_name) const {
  for (std::size_t i = 0; i < outputs_.size(); ++i) {
    if (outputs_[i].name == port_name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace mb
