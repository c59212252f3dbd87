#include "blocks/clock.h"

namespace mb {

Clock::Clock(const BlockConfig& config) : Block(config.name) {
  DeclareOutputPort("y");
  SetSampleTime(SampleTime::Continuous());
}

void Clock::CalcOutput(const BlockContext& c) const { c.y(0) = c.time(); }

MB_REGISTER_BLOCK(Clock, BlockType{
    "clock", "y = t, the simulation time [s] (Simulink's Clock). Out: y.", {}, SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Clock>(c); }})

}  // namespace mb
