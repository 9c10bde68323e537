// Helpers shared by the tests: the backends under test and small scenes.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include <carom/world.h>

#include "world/make_backend.h"

namespace carom::test {

// `engine` on the device under test. OpenCL uses the device named by
// CAROM_TEST_DEVICE (as --device), read when the test runs, else the
// default device; PoCL stands in for a GPU on machines without one.
inline EngineDef testEngine(ComputeEngine engine) {
    const char* device = std::getenv("CAROM_TEST_DEVICE");
    return EngineDef{engine, engine != ComputeEngine::Cpu && device ? device : ""};
}

// The backends and pipelines a test can be registered for; `label` ends the
// name of the test case that runs on it. A build without OpenCL registers
// the CPU only.
struct TestPipeline {
    ComputeEngine engine;
    const char* label;
};
inline constexpr TestPipeline kTestPipelines[] = {{ComputeEngine::Cpu, "cpu"},
                                                  {ComputeEngine::OpenClHostGrid, "opencl host-grid"},
                                                  {ComputeEngine::OpenClResident, "opencl resident"}};

// Which of kTestPipelines a test case is registered for.
enum class Registered { EveryPipeline, OpenClPipelines };

namespace registration {

using Body = void (*)(const EngineDef&);

// doctest's test case is a function without arguments: one per body and pipeline.
template <Body body, std::size_t slot>
void runOn() {
    body(testEngine(kTestPipelines[slot].engine));
}

// What doctest's TEST_CASE expands to, once for each pipeline of this build
// that `which` selects, named "name [label]". The pipeline's index is the
// case's template id, which orders the cases as kTestPipelines does; doctest
// keeps a templated case's name in m_full_name.
template <Body body, std::size_t... slots>
int registerCases(Registered which, const char* name, const char* file, unsigned line,
                  const doctest::detail::TestSuite& suite, std::index_sequence<slots...>) {
    const auto add = [&](std::size_t slot, doctest::detail::funcType test) {
        const TestPipeline& p = kTestPipelines[slot];
        const bool selected = which == Registered::EveryPipeline || p.engine != ComputeEngine::Cpu;
        if (!selected || !engineAvailable(p.engine)) return;
        doctest::detail::TestCase testCase(test, file, line, suite, doctest::String(), static_cast<int>(slot));
        testCase.m_full_name = (std::string(name) + " [" + p.label + "]").c_str();
        testCase.m_name = testCase.m_full_name.c_str();
        doctest::detail::regTest(testCase);
    };
    (add(slots, &runOn<body, slots>), ...);
    return 0;
}

}  // namespace registration

}  // namespace carom::test

// A test case registered once per backend and pipeline ("name [cpu]", "name
// [opencl host-grid]", "name [opencl resident]"), so a failure names the one that
// failed; the body gets the pipeline's EngineDef as `def`:
//     CAROM_BACKEND_TEST_CASE("periodic: ...") { const Run r = run(def, world, particles, 100); ... }
#define CAROM_BACKEND_TEST_CASE(name) CAROM_REGISTERED_TEST_CASE_(EveryPipeline, name, DOCTEST_ANONYMOUS(CAROM_CASE_))
// The same for the OpenCL pipelines only: comparisons of OpenCL against the CPU.
#define CAROM_OPENCL_TEST_CASE(name) CAROM_REGISTERED_TEST_CASE_(OpenClPipelines, name, DOCTEST_ANONYMOUS(CAROM_CASE_))

#define CAROM_REGISTERED_TEST_CASE_(which, name, body)                                                    \
    static void body(const ::carom::EngineDef& def);                                                      \
    DOCTEST_GLOBAL_NO_WARNINGS(DOCTEST_ANONYMOUS(CAROM_REGISTRATION_),                                    \
                               ::carom::test::registration::registerCases<body>(                          \
                                   ::carom::test::Registered::which, name, __FILE__, __LINE__,            \
                                   doctest_detail_test_suite_ns::getCurrentTestSuite(),                   \
                                   std::make_index_sequence<std::size(::carom::test::kTestPipelines)>())) \
    static void body(const ::carom::EngineDef& def)

namespace carom::test {

// Sets an environment variable for its lifetime (POSIX setenv: the tests
// run on Linux and macOS), then restores what was there.
class ScopedEnvironment {
public:
    ScopedEnvironment(const char* name, const char* value) : name_(name) {
        if (const char* before = std::getenv(name)) before_ = before;
        setenv(name, value, 1);
    }
    ~ScopedEnvironment() { before_ ? (void)setenv(name_.c_str(), before_->c_str(), 1) : (void)unsetenv(name_.c_str()); }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    std::string name_;
    std::optional<std::string> before_;
};

inline Particle disk(float x, float y, float vx, float vy, float mass = 1.0f, float radius = 1.0f) {
    Particle p{};
    p.position = float2{x, y};
    p.velocity = float2{vx, vy};
    p.mass = mass;
    p.radius = radius;
    return p;
}

inline WorldDef box(float width, float height, float dt = 0.01f) {
    WorldDef w;
    w.width = width;
    w.height = height;
    w.dt = dt;
    return w;
}

// What a run leaves: the particles, the contact totals and the images.
struct Run {
    std::vector<Particle> particles;
    ContactTotals contacts;
    std::vector<Image> images;
};

// Runs `steps` steps of `particles` on a fresh backend `def`.
inline Run run(const EngineDef& def, const WorldDef& world, const std::vector<Particle>& particles,
               std::uint64_t steps) {
    auto backend = makeBackend(def, world);
    backend->setParticles(particles);
    backend->step(steps);
    Run r;
    backend->readParticles(r.particles);
    r.contacts = backend->contacts();
    r.images = backend->images();
    return r;
}

// Runs `steps` steps of `particles` on a fresh backend and returns the result.
inline std::vector<Particle> simulate(const EngineDef& def, const WorldDef& world,
                                      const std::vector<Particle>& particles, std::uint64_t steps,
                                      std::uint64_t* collisions = nullptr, ContactTotals* contacts = nullptr,
                                      std::vector<Image>* images = nullptr) {
    Run r = run(def, world, particles, steps);
    if (collisions) *collisions = r.contacts.collisions;
    if (contacts) *contacts = r.contacts;
    if (images) *images = r.images;
    return std::move(r.particles);
}

}  // namespace carom::test
