#include "models/diagnosis/effect_registry.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/closest_names.h"
#include "models/diagnosis/amplitude_factor.h"

namespace mb {

EffectRegistry& EffectRegistry::Global() {
  static EffectRegistry registry;
  return registry;
}

bool EffectRegistry::Add(EffectType type) {
  const std::string name = type.name;
  if (name.empty()) throw std::logic_error("an effect registered without a name");
  if (!type.regressors || !type.propose) {
    throw std::logic_error(fmt::format("effect '{}' registered without its regressors or proposal rule", name));
  }
  if (type.block) throw std::logic_error(fmt::format("effect '{}': register its block with its block", name));
  // Every effect's columns may carry a third factor (amplitude_factor.h): a new row of the grammar gets it too.
  type.regressors = [own = std::move(type.regressors)](const EffectInstance& e, const DiagnosisSignals& s) {
    return WithAmplitudeFactor(own(e, s), e, s);
  };
  if (type.multiplier.empty() != type.modulator.empty()) {
    throw std::logic_error(fmt::format("effect '{}' names one factor of its pair, not both", name));
  }
  if (!type.multiplier.empty()) {
    const std::pair<std::string, std::string> pair{type.multiplier, type.modulator};
    if (const auto held = pairs_.find(pair); held != pairs_.end()) {
      const EffectType& other = effects_.at(held->second);
      if (other.generated == type.generated) {
        throw std::logic_error(fmt::format("effects '{}' and '{}' are both the pair {} × {}", other.name, name,
                                           pair.first, pair.second));
      }
      if (type.generated) return true;  // the hand-written effect holds the pair
      if (other.block) unclaimed_blocks_.emplace(other.name, *other.block);
      effects_.erase(held->second);
    }
    pairs_[pair] = name;
  }
  if (effects_.count(name) > 0) throw std::logic_error(fmt::format("effect '{}' registered twice", name));
  const auto it = effects_.emplace(name, std::move(type)).first;
  if (const auto pending = unclaimed_blocks_.find(name); pending != unclaimed_blocks_.end()) {
    it->second.block = std::move(pending->second);
    unclaimed_blocks_.erase(pending);
  }
  return true;
}

bool EffectRegistry::AddBlockTemplate(const std::string& effect_name, EffectBlockTemplate block) {
  if (block.block_type.empty() || block.element_name.empty() || !block.parameters) {
    throw std::logic_error(
        fmt::format("the block of effect '{}' has no block type, element name or parameters function", effect_name));
  }
  const auto it = effects_.find(effect_name);
  const bool taken = it != effects_.end() ? it->second.block.has_value() : unclaimed_blocks_.count(effect_name) > 0;
  if (taken) throw std::logic_error(fmt::format("effect '{}' has a block registered twice", effect_name));
  if (it != effects_.end()) {
    it->second.block = std::move(block);
  } else {
    unclaimed_blocks_.emplace(effect_name, std::move(block));
  }
  return true;
}

std::vector<std::string> EffectRegistry::UnclaimedBlockTemplates() const {
  std::vector<std::string> out;
  for (const auto& [name, block] : unclaimed_blocks_) out.push_back(name);
  return out;
}

const EffectType* EffectRegistry::Find(std::string_view name) const {
  const auto it = effects_.find(name);
  return it == effects_.end() ? nullptr : &it->second;
}

const EffectType* EffectRegistry::FindPair(const std::string& multiplier, const std::string& modulator) const {
  const auto it = pairs_.find({multiplier, modulator});
  return it == pairs_.end() ? nullptr : Find(it->second);
}

const EffectType& EffectRegistry::Get(std::string_view name) const {
  if (const EffectType* type = Find(name)) return *type;
  std::string known, guess;
  for (const EffectType* e : Effects()) known += (known.empty() ? "" : ", ") + e->name;
  for (const auto& s : Suggest(name)) guess += (guess.empty() ? "" : "' or '") + s;
  throw std::invalid_argument(fmt::format("unknown effect '{}'; {}: {}", name,
                                          guess.empty() ? "the catalogue has"
                                                        : fmt::format("did you mean '{}'? The catalogue has", guess),
                                          known));
}

std::vector<const EffectType*> EffectRegistry::Effects() const {
  std::vector<const EffectType*> out;
  for (const auto& [name, type] : effects_) out.push_back(&type);
  std::stable_sort(out.begin(), out.end(), [](const EffectType* a, const EffectType* b) {
    return a->catalogue_order < b->catalogue_order;
  });
  return out;
}

std::vector<std::string> EffectRegistry::Suggest(std::string_view name, std::size_t max_suggestions) const {
  std::vector<std::string> names;
  for (const auto& [known, type] : effects_) names.push_back(known);
  return ClosestNames(name, names, max_suggestions);
}

const EffectType& LookupEffect(std::string_view name) { return EffectRegistry::Global().Get(name); }

std::vector<std::string> RecordSpecificParameters(std::string_view block_type) {
  std::vector<std::string> out;
  for (const EffectType* e : EffectRegistry::Global().Effects()) {
    if (!e->block || e->block->block_type != block_type) continue;
    for (const auto& p : e->block->record_specific) {
      if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
    }
  }
  return out;
}

}  // namespace mb
