// A gas in a box, through carom's public API: create a world, fill it with a
// gas, step it and print its energy, which the default (pairwise) collision
// scheme conserves to rounding.
//
//     gas_in_a_box [cpu|opencl-host-grid|opencl-resident]
#include <cstdio>
#include <cstring>

#include <carom/carom.h>

int main(int argc, char** argv) {
    carom::SceneDef gas;  // disks of radius 1, mass 1 and speed 1 in a square box
    gas.particles = 2000;
    gas.packing = 0.5f;

    try {
        const carom::Scene scene = carom::makeScene(gas);
        carom::WorldDef def;
        def.width = scene.width;
        def.height = scene.height;
        if (argc > 1 && std::strcmp(argv[1], "opencl-host-grid") == 0)
            def.engine = carom::ComputeEngine::OpenClHostGrid;
        if (argc > 1 && std::strcmp(argv[1], "opencl-resident") == 0) def.engine = carom::ComputeEngine::OpenClResident;

        carom::World world(def);
        world.setDisks(scene.disks);
        std::printf("%zu disks in a %.1f x %.1f box on %s\n", world.diskCount(), def.width, def.height,
                    world.deviceName().c_str());
        const double initial = world.kineticEnergy();
        for (int block = 0; block < 5; ++block) {
            world.step(200);
            std::printf("t = %6.2f  energy %.9g  collisions %llu\n", world.time(), world.kineticEnergy(),
                        static_cast<unsigned long long>(world.measurements().collisions));
        }
        const carom::Measurements m = world.measurements();
        std::printf("kT %.6g, pressure on the walls %.6g, Z = %.4f\n", m.temperature, m.pressure, m.compressibility);
        std::printf("relative energy change %+.2e\n", (world.kineticEnergy() - initial) / initial);
    } catch (const carom::Error& e) {
        std::fprintf(stderr, "gas_in_a_box: %s\n", e.what());
        return 1;
    }
    return 0;
}
