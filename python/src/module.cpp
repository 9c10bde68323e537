// carom._carom: the Python extension, nanobind over the public C++ API
// (include/carom/). python/carom/ builds the Python API on it: argument
// checks, NumPy conversions and the documentation live there.
#include <carom/carom.h>
#include <carom/io.h>
#ifdef CAROM_HAVE_MPI
#include <carom/decomposition.h>
#endif

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using carom::Disk;
using carom::DiskMemory;
using carom::World;
using carom::WorldDef;
// A file's name as the OS spells it: a str or os.PathLike from Python, encoded
// as os.fsencode does, so that names that are not UTF-8 reach the file.
using Path = std::filesystem::path;

// Arrays from Python, already checked and converted by python/carom/_world.py.
using Pairs = nb::ndarray<const float, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;
using Values = nb::ndarray<const float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
// Read-only float32 arrays over a buffer of disk records.
using ReadPairs = nb::ndarray<nb::numpy, const float, nb::ndim<2>>;
using ReadValues = nb::ndarray<nb::numpy, const float, nb::ndim<1>>;

static_assert(offsetof(Disk, position) == DiskMemory::kPosition * sizeof(float) &&
                  offsetof(Disk, velocity) == DiskMemory::kVelocity * sizeof(float) &&
                  offsetof(Disk, mass) == DiskMemory::kMass * sizeof(float) &&
                  offsetof(Disk, radius) == DiskMemory::kRadius * sizeof(float),
              "a Disk's fields lie where a DiskMemory record's do, so one code path reads both");

std::vector<Disk> disksOf(const Pairs& positions, const Pairs& velocities, const Values& masses, const Values& radii) {
    const std::size_t n = positions.shape(0);
    if (velocities.shape(0) != n || masses.shape(0) != n || radii.shape(0) != n)
        throw carom::Error("positions, velocities, masses and radii: " + std::to_string(n) + ", " +
                           std::to_string(velocities.shape(0)) + ", " + std::to_string(masses.shape(0)) + " and " +
                           std::to_string(radii.shape(0)) + " disks; allowed: the same number in each");
    std::vector<Disk> disks(n);
    const float* x = positions.data();
    const float* v = velocities.data();
    for (std::size_t i = 0; i < n; ++i)
        disks[i] = Disk{{x[2 * i], x[2 * i + 1]}, {v[2 * i], v[2 * i + 1]}, masses.data()[i], radii.data()[i]};
    return disks;
}

// World::addDisks or World::editDisks with the arrays' disks.
template <void (World::*edit)(const Disk*, std::size_t)>
void editWith(World& world, const Pairs& positions, const Pairs& velocities, const Values& masses,
              const Values& radii) {
    const std::vector<Disk> disks = disksOf(positions, velocities, masses, radii);
    (world.*edit)(disks.data(), disks.size());
}

// A capsule that keeps `owner` alive as long as the arrays over its memory.
nb::capsule keeping(std::shared_ptr<const void> owner) {
    return nb::capsule(new std::shared_ptr<const void>(std::move(owner)),
                       [](void* p) noexcept { delete static_cast<std::shared_ptr<const void>*>(p); });
}

// positions, velocities, masses and radii over `count` records of `stride`
// floats from `base`; `owner` keeps them alive as long as any of the arrays.
nb::tuple arraysOver(const float* base, std::size_t count, std::size_t stride, std::shared_ptr<const void> owner) {
    static const float kNoDisks[DiskMemory::kRadius + 1] = {};
    if (count == 0) base = kNoDisks;
    nb::capsule keep = keeping(std::move(owner));
    const auto s = static_cast<std::int64_t>(stride);
    return nb::make_tuple(ReadPairs(base + DiskMemory::kPosition, {count, 2}, keep, {s, 1}),
                          ReadPairs(base + DiskMemory::kVelocity, {count, 2}, keep, {s, 1}),
                          ReadValues(base + DiskMemory::kMass, {count}, keep, {s}),
                          ReadValues(base + DiskMemory::kRadius, {count}, keep, {s}));
}

// A read-only (N, 2) array that owns `pairs`.
template <typename T>
nb::ndarray<nb::numpy, const T, nb::ndim<2>> pairArray(std::vector<std::array<T, 2>> pairs) {
    auto owned = std::make_shared<std::vector<std::array<T, 2>>>(std::move(pairs));
    static const T kNone[2] = {};
    const T* data = owned->empty() ? kNone : owned->front().data();
    const std::size_t count = owned->size();
    return nb::ndarray<nb::numpy, const T, nb::ndim<2>>(data, {count, 2}, keeping(std::move(owned)));
}

nb::tuple arraysOf(std::vector<Disk> disks) {
    auto copy = std::make_shared<std::vector<Disk>>(std::move(disks));
    const float* base = copy->empty() ? nullptr : &copy->front().position.x;
    const std::size_t count = copy->size();
    return arraysOver(base, count, sizeof(Disk) / sizeof(float), std::move(copy));
}

// The CPU engine's own memory where it has it, else a copy.
nb::tuple diskArrays(const World& world) {
    DiskMemory memory = world.diskMemory();
    if (memory.base == nullptr) return arraysOf(world.disks());
    const float* base = memory.base;
    const std::size_t count = memory.count, stride = memory.stride;
    return arraysOver(base, count, stride, std::move(memory.owner));
}

// Steps with the GIL released, so that other threads run meanwhile (the
// package's World takes a lock per world around every call, so that none
// reads or changes it mid-step). The world's stop check takes the GIL back
// about every 20 ms to run Python's signal handlers: Ctrl-C stops the call
// even within a step, the world holding the last step it completed.
void stepReleasingTheGil(World& world, std::uint64_t steps) {
    bool interrupted = false;
    struct StopCheck {
        World& world;
        ~StopCheck() { world.setStopCheck({}); }
    } clear{world};
    world.setStopCheck([&interrupted] {
        nb::gil_scoped_acquire python;
        interrupted = PyErr_CheckSignals() != 0;
        return interrupted;
    });
    {
        nb::gil_scoped_release released;
        world.step(steps);
    }
    if (interrupted) throw nb::python_error();
}

nb::dict dictOf(const carom::Measurements& m) {
    nb::dict d;
    d["time"] = m.time;
    d["steps"] = m.steps;
    d["collisions"] = m.collisions;
    d["collision_rate"] = m.collisionRate;
    d["temperature"] = m.temperature;
    d["pressure"] = m.pressure;
    d["compressibility"] = m.compressibility;
    d["collision_virial"] = m.collisionVirial;
    d["wall_pressure"] = m.wallPressure;
    d["substeps"] = m.substeps;
    d["late_contacts"] = m.lateContacts;
    d["max_rounds"] = m.maxRounds;
    return d;
}

nb::dict dictOf(const carom::Device& d) {
    nb::dict entry;
    entry["index"] = d.index;
    entry["name"] = d.name;
    entry["platform"] = d.platform;
    entry["type"] = d.type;
    entry["version"] = d.version;
    entry["memory_bytes"] = d.memoryBytes;
    entry["bitwise_reproducible"] = d.correctlyRoundedDivideSqrt;
    return entry;
}

nb::dict dictOf(const carom::EventCounts& c) {
    nb::dict d;
    d["collisions"] = c.collisions;
    d["wall_bounces"] = c.wallBounces;
    d["cell_crossings"] = c.cellCrossings;
    d["stale"] = c.stale;
    d["overlapping"] = c.overlapping;
    return d;
}

// convert(value), its refusal prefixed with the argument's name.
template <class Convert, class Value>
float named(const std::string& name, Convert convert, const Value& value) {
    try {
        return convert(value);
    } catch (const carom::Error& e) {
        throw carom::Error(name + ": " + e.what());
    }
}

WorldDef worldDef(float width, float height, float dt, std::array<float, 2> gravity, const std::string& boundary,
                  const std::string& collisions, const std::string& engine, const std::string& device, float maxTravel,
                  float skin) {
    WorldDef def;
    def.width = width;
    def.height = height;
    def.dt = dt;
    def.gravity = {gravity[0], gravity[1]};
    def.boundary = carom::parseBoundary(boundary);
    def.collisions = carom::parseCollisionScheme(collisions);
    def.engine = carom::parseComputeEngine(engine);
    def.device = device;
    def.maxTravel = maxTravel;
    def.skin = skin;
    return def;
}

// Splits `def` among the processes of the communicator whose Fortran handle
// is `comm` (mpi4py's Comm.py2f()), in domains[0] x domains[1] domains (0 x 0:
// chosen from the box), gathering the whole world each step or on request
// (python/carom/_world.py checked `gather`); nothing for no communicator.
void decompose(WorldDef& def, std::optional<std::int64_t> comm, std::array<int, 2> domains, const std::string& gather) {
    if (!comm) return;
#ifdef CAROM_HAVE_MPI
    def.decomposition =
        carom::makeDecomposition({MPI_Comm_f2c(static_cast<MPI_Fint>(*comm)), domains[0], domains[1],
                                  gather == "on_request" ? carom::Gather::OnRequest : carom::Gather::EachStep});
#else
    (void)def;
    (void)domains;
    (void)gather;
    throw carom::Error("comm: this carom was built without MPI; allowed: None (docs/mpi.md says how to build with it)");
#endif
}

}  // namespace

NB_MODULE(_carom, m) {
    m.doc() = "carom's C++ library; use the package `carom`, which builds its API on this module.";

    // carom.Error: everything carom raises; carom.InputError (also a
    // ValueError): the library's refusals of bad input (carom::Error).
    // The types live as long as the process (the translator may run until its end).
    static PyObject* error = PyErr_NewException("carom.Error", PyExc_Exception, nullptr);
    static PyObject* inputError = PyErr_NewException(
        "carom.InputError", nb::make_tuple(nb::handle(error), nb::handle(PyExc_ValueError)).ptr(), nullptr);
    m.attr("Error") = nb::handle(error);
    m.attr("InputError") = nb::handle(inputError);
    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const carom::Error& e) {
            // A message may name a path that is not UTF-8: its bytes as \xNN.
            PyObject* message = PyUnicode_DecodeUTF8(e.what(), Py_ssize_t(std::strlen(e.what())), "backslashreplace");
            PyErr_SetObject(inputError, message);
            Py_XDECREF(message);
        }
    });

    // The package's real-valued arguments (numbers only: text is refused)
    // go through carom's one float32 rule (carom/io.h), each refusal naming
    // the argument.
    m.def(
        "to_float", [](const std::string& name, double value) { return named(name, carom::io::toFloat, value); },
        "name"_a, "value"_a);
    m.attr("VERSION") = carom::version();
#ifdef CAROM_HAVE_MPI
    m.attr("HAVE_MPI") = true;
#else
    m.attr("HAVE_MPI") = false;
#endif
    m.def(
        "engine_available",
        [](const std::string& engine) { return carom::engineAvailable(carom::parseComputeEngine(engine)); },
        "engine"_a);
    m.def("devices", [] {
        nb::list out;
        for (const carom::Device& d : carom::listDevices()) out.append(dictOf(d));
        return out;
    });
    m.def(
        "find_device", [](const std::string& selector) { return dictOf(carom::findDevice(selector)); }, "selector"_a);
    // The engine of pipeline=None (--pipeline auto) on the device `selector` selects.
    m.def(
        "opencl_engine_for",
        [](const std::string& selector) {
            return carom::computeEngineName(carom::openClEngineFor(carom::findDevice(selector)));
        },
        "selector"_a);

    // carom::chooseEngine: (engine, device selector, reason), World(engine="auto")'s choice.
    m.def("choose_engine", [] {
        const carom::EngineChoice choice = carom::chooseEngine();
        return nb::make_tuple(carom::computeEngineName(choice.engine.engine), choice.engine.device, choice.reason);
    });

    m.def(
        "make_scene",
        [](std::uint32_t particles, float packing, float width, float height, std::array<float, 2> radius,
           std::array<float, 2> mass, float speed, std::uint64_t seed) {
            carom::SceneDef def;
            def.particles = particles;
            def.packing = packing;
            def.width = width;
            def.height = height;
            def.radiusMin = radius[0];
            def.radiusMax = radius[1];
            def.massMin = mass[0];
            def.massMax = mass[1];
            def.speed = speed;
            def.seed = seed;
            carom::Scene scene = carom::makeScene(def);
            return nb::make_tuple(scene.width, scene.height, arraysOf(std::move(scene.disks)));
        },
        "particles"_a, "packing"_a, "width"_a, "height"_a, "radius"_a, "mass"_a, "speed"_a, "seed"_a);

    m.def(
        "read_state", [](const Path& path) { return arraysOf(carom::io::readState(path.native())); }, "path"_a);
    m.def(
        "write_state", [](const Path& path, const World& world) { carom::io::writeState(path.native(), world); },
        "path"_a, "world"_a);
    m.def(
        "write_xyz",
        [](const Path& path, const World& world, bool append) {
            carom::io::TrajectoryWriter writer =
                append ? carom::io::TrajectoryWriter(path.native(), world) : carom::io::TrajectoryWriter(path.native());
            writer.write(world);
            writer.close();
        },
        "path"_a, "world"_a, "append"_a);

    nb::class_<World>(m, "World")
        .def(nb::new_([](float width, float height, float dt, std::array<float, 2> gravity, const std::string& boundary,
                         const std::string& collisions, const std::string& engine, const std::string& device,
                         float maxTravel, float skin, std::optional<std::int64_t> comm, std::array<int, 2> domains,
                         const std::string& gather) {
                 WorldDef def =
                     worldDef(width, height, dt, gravity, boundary, collisions, engine, device, maxTravel, skin);
                 decompose(def, comm, domains, gather);
                 return World(def);
             }),
             "width"_a, "height"_a, "dt"_a, "gravity"_a, "boundary"_a, "collisions"_a, "engine"_a, "device"_a,
             "max_travel"_a, "skin"_a, "comm"_a.none() = nb::none(), "domains"_a = std::array<int, 2>{0, 0},
             "gather"_a = "each_step")
        .def_static(
            "from_scene_file",
            [](const Path& path, const std::string& engine, const std::string& device, std::optional<float> maxTravel,
               float skin, std::optional<std::int64_t> comm, std::array<int, 2> domains, const std::string& gather) {
                carom::SceneFileDef file = carom::io::readSceneFile(path.native());
                file.world.engine = carom::parseComputeEngine(engine);
                file.world.device = device;
                if (maxTravel) file.world.maxTravel = *maxTravel;  // else the file's (dt = "auto" sets it)
                file.world.skin = skin;
                decompose(file.world, comm, domains, gather);
                const carom::io::SceneFile scene = carom::io::loadScene(file);
                World world(scene.world);
                world.setDisks(scene.disks, path.native());
                return nb::make_tuple(std::move(world), scene.steps);
            },
            "path"_a, "engine"_a, "device"_a, "max_travel"_a, "skin"_a, "comm"_a.none() = nb::none(),
            "domains"_a = std::array<int, 2>{0, 0}, "gather"_a = "each_step")
        .def_static(
            "from_checkpoint",
            [](const Path& path, const std::string& engine, const std::string& device, float maxTravel, float skin,
               std::optional<std::int64_t> comm, std::array<int, 2> domains, const std::string& gather) {
                // loadCheckpoint takes only the engine, the device, maxTravel, the skin and the decomposition from it
                WorldDef def;
                def.engine = carom::parseComputeEngine(engine);
                def.device = device;
                def.maxTravel = maxTravel;
                def.skin = skin;
                decompose(def, comm, domains, gather);
                return carom::io::loadCheckpoint(path.native(), def);
            },
            "path"_a, "engine"_a, "device"_a, "max_travel"_a, "skin"_a, "comm"_a.none() = nb::none(),
            "domains"_a = std::array<int, 2>{0, 0}, "gather"_a = "each_step")
        .def(
            "save_checkpoint", [](const World& w, const Path& path) { carom::io::saveCheckpoint(path.native(), w); },
            "path"_a)
        .def("copy",
             [](const World& w) {
                 World copy(w.def());  // the same engine and device selector, dt, gravity and maxTravel
                 if (w.diskCount() > 0) copy.restore(w.snapshot());
                 return copy;
             })
        .def(
            "set_disks",
            [](World& w, const Pairs& positions, const Pairs& velocities, const Values& masses, const Values& radii,
               bool refuseDeepOverlaps) {
                w.setDisks(disksOf(positions, velocities, masses, radii), "set_disks",
                           refuseDeepOverlaps ? carom::DeepOverlaps::Refuse : carom::DeepOverlaps::Warn);
            },
            "positions"_a, "velocities"_a, "masses"_a, "radii"_a, "refuse_deep_overlaps"_a)
        .def("add_disks", &editWith<&World::addDisks>, "positions"_a, "velocities"_a, "masses"_a, "radii"_a)
        .def("edit_disks", &editWith<&World::editDisks>, "positions"_a, "velocities"_a, "masses"_a, "radii"_a)
        .def(
            "set_disk",
            [](World& w, std::size_t id, std::array<float, 2> position, std::array<float, 2> velocity, float mass,
               float radius) {
                w.setDisk(id, Disk{{position[0], position[1]}, {velocity[0], velocity[1]}, mass, radius});
            },
            "id"_a, "position"_a, "velocity"_a, "mass"_a, "radius"_a)
        .def(
            "place",
            [](World& w, std::uint32_t count, std::array<float, 2> radius, std::array<float, 2> mass, float speed,
               float temperature, std::uint64_t seed) {
                carom::SceneFileDef file;
                file.path = "World.place";
                file.world = w.def();
                file.seed = seed;
                carom::GroupDef group;
                group.name = "the disks";
                group.count = count;
                group.radiusMin = radius[0];
                group.radiusMax = radius[1];
                group.massMin = mass[0];
                group.massMax = mass[1];
                group.speed = speed;
                group.temperature = temperature;
                file.groups.push_back(group);
                w.setDisks(carom::makeScene(file).disks, "World.place");
            },
            "count"_a, "radius"_a, "mass"_a, "speed"_a, "temperature"_a, "seed"_a)
        .def("step", &stepReleasingTheGil, "steps"_a)
        // bench/python_overhead.py: the same steps through the C++ API alone, timed in C++.
        .def(
            "_cpp_step_seconds",
            [](World& w, std::uint64_t steps) {
                const auto start = std::chrono::steady_clock::now();
                w.step(steps);
                return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            },
            "steps"_a)
        .def("disk_arrays", &diskArrays)
        .def("exact_positions", [](const World& w) { return pairArray(w.exactPositions()); })
        .def("images", [](const World& w) { return pairArray(w.images()); })
        .def("own_disks",
             [](const World& w) {
                 carom::OwnDisks own = w.ownDisks();
                 auto ids = std::make_shared<std::vector<std::uint32_t>>(std::move(own.ids));
                 static const std::uint32_t kNone = 0;
                 const std::uint32_t* data = ids->empty() ? &kNone : ids->data();
                 const std::size_t count = ids->size();
                 return nb::make_tuple(
                     nb::ndarray<nb::numpy, const std::uint32_t, nb::ndim<1>>(data, {count}, keeping(std::move(ids))),
                     arraysOf(std::move(own.disks)), pairArray(std::move(own.images)));
             })
        .def("gather", &World::gather)
        .def(
            "set_motion",
            [](World& w, float dt, std::array<float, 2> g) {
                w.setMotion(dt, {g[0], g[1]});
            },
            "dt"_a, "gravity"_a)
        .def("measurements", [](const World& w) { return dictOf(w.measurements()); })
        .def("reset_measurements", &World::resetMeasurements)
        .def("event_counts", [](const World& w) { return dictOf(w.eventCounts()); })
        .def_prop_ro("disk_count", &World::diskCount)
        .def_prop_ro("step_count", &World::stepCount)
        .def_prop_ro("time", &World::time)
        .def_prop_ro("width", [](const World& w) { return w.def().width; })
        .def_prop_ro("height", [](const World& w) { return w.def().height; })
        .def_prop_ro("dt", [](const World& w) { return w.def().dt; })
        .def_prop_ro("gravity",
                     [](const World& w) {
                         return std::array<float, 2>{w.def().gravity.x, w.def().gravity.y};
                     })
        .def_prop_ro("boundary", [](const World& w) { return carom::boundaryName(w.def().boundary); })
        .def_prop_ro("collision_scheme", [](const World& w) { return carom::collisionSchemeName(w.def().collisions); })
        .def_prop_ro("engine", [](const World& w) { return carom::computeEngineName(w.def().engine); })
        .def_prop_ro("max_travel", [](const World& w) { return w.def().maxTravel; })
        .def_prop_ro("skin", [](const World& w) { return w.def().skin; })
        .def_prop_ro("kinetic_energy", &World::kineticEnergy)
        .def_prop_ro("potential_energy", &World::potentialEnergy)
        .def_prop_ro("total_energy", &World::totalEnergy)
        .def_prop_ro("momentum", &World::momentum)
        .def_prop_ro("temperature", &World::temperature)
        .def_prop_ro("collision_count", &World::collisionCount)
        .def_prop_ro("max_overlap", &World::maxOverlap)
        .def_prop_ro("escaped_count", &World::escapedCount)
        .def_prop_ro("warnings", &World::warnings)
        .def_prop_ro("bitwise_reproducible", &World::bitwiseReproducible)
        .def_prop_ro("device_name", &World::deviceName)
        .def_prop_ro("device_memory", [](const World& w) {
            const carom::DeviceMemoryUse use = w.deviceMemory();
            nb::dict d;
            d["bytes"] = use.bytes;
            d["peak_bytes"] = use.peakBytes;
            return d;
        });
}
