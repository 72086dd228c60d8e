// An F´ active component's rate-group handler around kairos, in C++ against kairos.h alone
// (docs/embedding.md, "F´"): each tick of the rate group (schedIn) the component hands the
// executive the telemetry it received since the last tick, as (channel id, value), and sends the
// commands it returns, as (opcode, arguments). It is shaped like the class `fpp-to-cpp`
// generates a base for, without F´'s headers: the ports are plain virtual functions here.
//
// main() wires it to a simulated propulsion subsystem (the hardware of
// scenarios/propulsion/plant.ron: the PDE relays commands while on, the engine heats for 40 s,
// an open valve passes its tank's pressure) and fires the engine from cold, as the scenario
// scenarios/propulsion/nominal.ron does. Built and run by kairos-ffi/tests/c_examples.rs:
//   c++ -std=c++17 -I kairos-ffi/include examples/cpp/propulsion_component.cpp
//       target/debug/libkairos_ffi.a -lpthread -ldl -lm
//   ./a.out models/propulsion.ron programs/propulsion_fire.rmpl
//       models/fprime/PropulsionTopologyDictionary.json models/fprime/propulsion.binding.ron
// (each command on one line).
// It prints each command it sends and exits 0 when the engine fires and the executive settles.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "kairos.h"

namespace Prop {

// Channel ids and opcodes, as the dictionary numbers them (base id 0x120).
enum Channel : std::uint32_t {
    VALVE1_OUTLET = 0x120,
    VALVE2_OUTLET = 0x121,
    ENGINE_POWER = 0x122,
    ENGINE_TEMP = 0x123,
    ENGINE_THRUST = 0x124,
    TANK1_PRESSURE = 0x125,
};
enum Opcode : std::uint32_t {
    PDE_ON = 0x120,
    PDE_OFF = 0x121,
    PDE_RESET = 0x122,
    VALVE_OPEN = 0x123,
    VALVE_CLOSE = 0x124,
    ENGINE_STANDBY = 0x125,
    ENGINE_FIRE = 0x126,
    ENGINE_OFF = 0x127,
};

// The deleters of what kairos allocates, so that ownership is the compiler's to keep.
struct ExecutiveFree {
    void operator()(KairosExecutive* executive) const { kairos_executive_free(executive); }
};
struct StepFree {
    void operator()(KairosStep* step) const { kairos_step_free(step); }
};
using Executive = std::unique_ptr<KairosExecutive, ExecutiveFree>;
using Step = std::unique_ptr<KairosStep, StepFree>;

// The component: telemetry in (tlmIn, queued until the next tick), commands out (cmdOut) on
// each rate-group tick (schedIn_handler).
class KairosComponent {
  public:
    KairosComponent(const char* plant, const char* program, const char* dictionary, const char* binding) {
        KairosOptions options = kairos_options_default();
        options.kappa = 5;
        KairosExecutive* raw = nullptr;
        char* error = nullptr;
        if (kairos_executive_load(plant, program, &options, &raw, &error) != KAIROS_STATUS_OK) {
            std::string message = error != nullptr ? error : "unknown error";
            kairos_string_free(error);
            throw std::runtime_error(message);
        }
        executive_.reset(raw);
        if (kairos_executive_bind_fprime(raw, dictionary, binding) != KAIROS_STATUS_OK) {
            throw std::runtime_error(kairos_executive_last_error(raw));
        }
    }
    virtual ~KairosComponent() = default;

    // Telemetry received from the other components (an F´ telemetry port would call this).
    void tlmIn(std::uint32_t channel, std::int64_t value) {
        queued_.push_back(KairosTelemetry{channel, KAIROS_TLM_ENUM, value, 0.0});
    }
    void tlmInFloat(std::uint32_t channel, double value) {
        queued_.push_back(KairosTelemetry{channel, KAIROS_TLM_FLOAT, 0, value});
    }

    // The rate group's tick at `now` seconds: one executive cycle. Returns true once the program
    // has completed and nothing is left to command.
    bool schedIn_handler(double now) {
        KairosStep* raw = nullptr;
        KairosStatus status = kairos_fprime_step(executive_.get(), now, queued_.data(), queued_.size(), &raw);
        queued_.clear();
        if (status != KAIROS_STATUS_OK) {
            throw std::runtime_error(kairos_executive_last_error(executive_.get()));
        }
        Step step(raw);
        KairosStepSummary summary = kairos_step_summary(step.get());
        for (std::size_t i = 0; i < summary.event_count; i++) {
            KairosEvent event = kairos_step_event(step.get(), i);
            if (event.kind == KAIROS_EVENT_KIND_DIAGNOSIS) {
                std::printf("%6.1f s  diagnosis: %s\n", now, event.line);
            }
        }
        for (std::size_t i = 0; i < summary.fprime_command_count; i++) {
            KairosFprimeCommand command = kairos_step_fprime_command(step.get(), i);
            std::vector<std::int64_t> args;
            for (std::size_t a = 0; a < command.arg_count; a++) {
                args.push_back(kairos_step_fprime_arg(step.get(), i, a).integer);
            }
            std::printf("%6.1f s  send %s (opcode 0x%x)", now, command.name, command.opcode);
            for (std::int64_t arg : args) {
                std::printf(" %lld", static_cast<long long>(arg));
            }
            std::printf("\n");
            cmdOut(now, command.opcode, args);
        }
        return (summary.flags & KAIROS_STEP_SETTLED) != 0;
    }

  protected:
    // The command output port: the deployment's command dispatcher is behind it.
    virtual void cmdOut(double now, std::uint32_t opcode, const std::vector<std::int64_t>& args) = 0;

  private:
    Executive executive_;
    std::vector<KairosTelemetry> queued_;
};

}  // namespace Prop

// The propulsion hardware, commanded by opcode, reporting by channel.
class Propulsion : public Prop::KairosComponent {
  public:
    using KairosComponent::KairosComponent;

    std::vector<std::string> sent;

    // Reports every channel, as its components would each tick.
    void report(double now) {
        if (engine_heating_ && now - heating_since_ >= 40.0) {
            engine_hot_ = true;
        }
        tlmIn(Prop::VALVE1_OUTLET, valve_open_[0] ? 1 : 0);
        tlmIn(Prop::VALVE2_OUTLET, valve_open_[1] ? 1 : 0);
        tlmIn(Prop::ENGINE_POWER, engine_powered_ ? 1 : 0);
        tlmIn(Prop::ENGINE_TEMP, engine_hot_ ? 1 : 0);
        tlmIn(Prop::ENGINE_THRUST, engine_firing_ ? 1 : 0);
        tlmInFloat(Prop::TANK1_PRESSURE, 2100.0);  // not bound: ignored
    }

  protected:
    void cmdOut(double now, std::uint32_t opcode, const std::vector<std::int64_t>& args) override {
        std::string name = std::to_string(opcode);
        for (std::int64_t arg : args) {
            name += " " + std::to_string(arg);
        }
        sent.push_back(name);
        switch (opcode) {
            case Prop::PDE_ON: pde_on_ = true; break;
            case Prop::PDE_OFF: pde_on_ = false; break;
            case Prop::VALVE_OPEN:
                if (pde_on_ && !args.empty() && (args[0] == 1 || args[0] == 2)) valve_open_[args[0] - 1] = true;
                break;
            case Prop::VALVE_CLOSE:
                if (pde_on_ && !args.empty() && (args[0] == 1 || args[0] == 2)) valve_open_[args[0] - 1] = false;
                break;
            case Prop::ENGINE_STANDBY:
                if (pde_on_ && !engine_powered_) {
                    engine_powered_ = true;
                    engine_heating_ = true;
                    heating_since_ = now;
                }
                break;
            case Prop::ENGINE_FIRE:
                if (pde_on_ && engine_hot_ && valve_open_[0] && valve_open_[1]) engine_firing_ = true;
                break;
            case Prop::ENGINE_OFF:
                if (pde_on_) engine_powered_ = engine_heating_ = engine_hot_ = engine_firing_ = false;
                break;
            default: break;
        }
    }

  private:
    bool pde_on_ = false;
    bool valve_open_[2] = {false, false};
    bool engine_powered_ = false;
    bool engine_heating_ = false;
    bool engine_hot_ = false;
    bool engine_firing_ = false;
    double heating_since_ = 0.0;
};

int main(int argc, char** argv) {
    if (argc != 5) {
        std::fprintf(stderr, "usage: %s PLANT PROGRAM DICTIONARY BINDING\n", argv[0]);
        return 2;
    }
    try {
        Propulsion propulsion(argv[1], argv[2], argv[3], argv[4]);
        for (int tick = 0; tick <= 300; tick++) {
            double now = tick;
            propulsion.report(now);
            if (propulsion.schedIn_handler(now)) {
                std::printf("%6.1f s  settled after %zu commands\n", now, propulsion.sent.size());
                return 0;
            }
        }
        std::fprintf(stderr, "the engine did not fire in 300 s\n");
        return 1;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "%s\n", error.what());
        return 2;
    }
}
