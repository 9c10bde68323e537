// The page's engine: a carom::World on the CPU engine, compiled to
// WebAssembly, behind the few calls page.js makes (embind). A call that
// fails returns the carom::Error's message and leaves the world as it was,
// so that a bad scene file or link never stops the running scene.
#include <emscripten/bind.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <carom/carom.h>
#include <carom/io.h>

#include "app/validate/statistics.h"

namespace {

using carom::Disk;

// What the plots read after each frame, in the units of carom/world.h.
struct Observables {
    double time = 0.0;
    double steps = 0.0;  // a double: JavaScript numbers hold every step count a page reaches
    double kinetic = 0.0;
    double potential = 0.0;
    double total = 0.0;
    double temperature = 0.0;
    double collisions = 0.0;
};

// Pressure and Z since the last takeMeasurements (or the scene's start).
struct Window {
    double time = 0.0;
    double collisions = 0.0;
    double pressure = 0.0;
    double compressibility = 0.0;
};

class Simulation {
public:
    // Reads a scene file's text (`name` names it in messages), places its
    // disks and makes them the running scene: "" on success, else the message.
    std::string load(const std::string& text, const std::string& name) {
        return attempt([&] {
            carom::io::SceneFile scene = carom::io::loadScene(carom::io::parseSceneFile(text, name));
            scene.world.engine = carom::ComputeEngine::Cpu;
            auto world = std::make_unique<carom::World>(scene.world);
            world->setDisks(scene.disks, name);
            world_ = std::move(world);
            refresh();
        });
    }

    std::string step(double steps) {
        return attempt([&] {
            if (!(steps >= 0 && steps <= 1e6 && steps == std::floor(steps)))
                throw carom::Error("steps = " + text(steps) + "; allowed: whole numbers from 0 to 1000000");
            try {
                world().step(std::uint64_t(steps));
            } catch (const carom::Error&) {
                refresh();  // the world holds the last step it completed: show that one
                throw;
            }
            refresh();
        });
    }

    // The disks in id order, 6 floats each: x, y, vx, vy, mass, radius (carom::Disk).
    // A view of the module's memory, valid until the next call.
    emscripten::val disks() const {
        return emscripten::val(emscripten::typed_memory_view(disks_.size() * 6, &disks_.data()->position.x));
    }
    double width() const { return world().def().width; }
    double height() const { return world().def().height; }
    bool periodic() const { return world().def().boundary == carom::Boundary::Periodic; }
    std::string scheme() const { return carom::collisionSchemeName(world().def().collisions); }

    Observables observables() const {
        const carom::World& w = world();
        Observables o;
        o.time = w.time();
        o.steps = double(w.stepCount());
        o.kinetic = w.kineticEnergy();
        o.potential = w.potentialEnergy();
        o.total = w.totalEnergy();
        o.temperature = w.temperature();
        o.collisions = double(w.collisionCount());
        return o;
    }

    Window takeMeasurements() {
        const carom::Measurements m = world().measurements();
        world().resetMeasurements();
        return Window{m.time, double(m.collisions), m.pressure, m.compressibility};
    }

    std::string setGravity(double gx, double gy) {
        return attempt([&] { world().setMotion(world().def().dt, carom::Vec2{float(gx), float(gy)}); });
    }

    // Moves disk `id` to (x, y) with velocity (vx, vy): the hand that grabs and throws.
    std::string setDisk(double id, double x, double y, double vx, double vy) {
        return attempt([&] {
            world();  // "no scene is loaded" comes first
            if (!(id >= 0 && id < double(disks_.size()) && id == std::floor(id)))
                throw carom::Error("disk " + text(id) + " does not exist; allowed: ids from 0 to " +
                                   std::to_string(disks_.size() - 1));
            Disk disk = disks_[std::size_t(id)];
            disk.position = {float(x), float(y)};
            disk.velocity = {float(vx), float(vy)};
            world().setDisk(std::size_t(id), disk);
            refresh();
        });
    }

    // Adds `count` disks of `radius` and `mass` on a ring around (x, y), flying outwards at `speed`.
    std::string burst(double x, double y, double count, double radius, double mass, double speed) {
        return attempt([&] {
            std::vector<Disk> added;
            const double ring = 2.2 * radius * std::fmax(1.0, count / (2.0 * carom::kPi * 1.1));
            for (int i = 0; i < int(count); ++i) {
                const double angle = 2.0 * carom::kPi * i / count;
                const double c = std::cos(angle), s = std::sin(angle);
                Disk d;
                d.position = {float(x + ring * c), float(y + ring * s)};
                d.velocity = {float(speed * c), float(speed * s)};
                d.mass = float(mass);
                d.radius = float(radius);
                added.push_back(d);
            }
            world().addDisks(added.data(), added.size());
            refresh();
        });
    }

    // FNV-1a 64 of the disks' floats in id order (little-endian bytes) and of
    // the collision count: the hash tests/web compares with the native engine's.
    std::string stateHash() const {
        std::uint64_t hash = 0xcbf29ce484222325ull;
        const auto add = [&](std::uint64_t value, int bytes) {
            for (int i = 0; i < bytes; ++i) {
                hash ^= (value >> (8 * i)) & 0xff;
                hash *= 0x100000001b3ull;
            }
        };
        for (const Disk& d : disks_) {
            for (float value : {d.position.x, d.position.y, d.velocity.x, d.velocity.y, d.mass, d.radius}) {
                std::uint32_t bits = 0;
                std::memcpy(&bits, &value, sizeof bits);
                add(bits, 4);
            }
        }
        add(world().collisionCount(), 8);
        char text[19];
        std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
        return text;
    }

private:
    static std::string text(double value) {
        char out[32];
        std::snprintf(out, sizeof out, "%g", value);
        return out;
    }
    template <class F>
    std::string attempt(F&& f) {
        try {
            f();
            return "";
        } catch (const std::exception& e) {
            return e.what();
        }
    }
    carom::World& world() {
        if (!world_) throw carom::Error("no scene is loaded");
        return *world_;
    }
    const carom::World& world() const {
        if (!world_) throw carom::Error("no scene is loaded");
        return *world_;
    }
    // Into the same buffer each time: no allocation a frame.
    void refresh() {
        disks_.resize(world_->diskCount());
        world_->getDisks(disks_.data(), disks_.size());
    }

    std::unique_ptr<carom::World> world_;
    std::vector<Disk> disks_;
};

}  // namespace

EMSCRIPTEN_BINDINGS(carom) {
    using namespace emscripten;
    value_object<Observables>("Observables")
        .field("time", &Observables::time)
        .field("steps", &Observables::steps)
        .field("kinetic", &Observables::kinetic)
        .field("potential", &Observables::potential)
        .field("total", &Observables::total)
        .field("temperature", &Observables::temperature)
        .field("collisions", &Observables::collisions);
    value_object<Window>("Window")
        .field("time", &Window::time)
        .field("collisions", &Window::collisions)
        .field("pressure", &Window::pressure)
        .field("compressibility", &Window::compressibility);
    class_<Simulation>("Simulation")
        .constructor<>()
        .function("load", &Simulation::load)
        .function("step", &Simulation::step)
        .function("disks", &Simulation::disks)
        .function("width", &Simulation::width)
        .function("height", &Simulation::height)
        .function("periodic", &Simulation::periodic)
        .function("scheme", &Simulation::scheme)
        .function("observables", &Simulation::observables)
        .function("takeMeasurements", &Simulation::takeMeasurements)
        .function("setGravity", &Simulation::setGravity)
        .function("setDisk", &Simulation::setDisk)
        .function("burst", &Simulation::burst)
        .function("stateHash", &Simulation::stateHash);
    // The published hard-disk equation of state and the 2D Maxwell-Boltzmann
    // speed density, from the sources `carom validate` checks against.
    function("referenceZ", &carom::validation::referenceZ);
    function("rayleighPdf", &carom::validation::rayleighPdf);
    constant("version", std::string(carom::version()));
}
