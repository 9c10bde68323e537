// A tour of carom's C++ API (docs/cpp-library.md shows it part by part): a
// periodic gas and its pressure, edits between steps, a scene file, and the
// files carom::io writes, a checkpoint continued bit for bit among them.
//
//     tour SCENE.toml        (e.g. scenes/mixture.toml); writes its files here
#include <carom/carom.h>
#include <carom/io.h>

#include <cstdio>
#include <cstring>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: tour SCENE.toml\n");
        return 2;
    }
    try {
        // A periodic gas at packing 0.5, and its equation of state.
        carom::SceneDef gas;
        gas.particles = 2000;
        gas.packing = 0.5f;
        gas.seed = 3;
        carom::Scene scene = carom::makeScene(gas);

        carom::WorldDef def;
        def.width = scene.width;
        def.height = scene.height;
        def.boundary = carom::Boundary::Periodic;
        carom::World world(def);
        world.setDisks(scene.disks);
        world.step(200);            // let the lattice melt
        world.resetMeasurements();  // measure from here on
        world.step(1000);
        carom::Measurements m = world.measurements();
        std::printf("kT %.4f, Z = %.3f, %.3f collisions per disk per unit time\n", m.temperature, m.compressibility,
                    m.collisionRate);

        // Edits between steps: read the disks, throw one, drop two more.
        std::vector<carom::Disk> disks = world.disks();  // in id order
        carom::Disk thrown = disks[0];
        thrown.velocity = {5.0f, 0.0f};
        world.setDisk(0, thrown);
        carom::Disk extra[2];
        extra[0].position = {1.5f, 1.5f};
        extra[1].position = {def.width - 1.5f, 1.5f};
        world.addDisks(extra, 2);  // may overlap a neighbour: the next steps part them
        world.step(10);
        std::printf("%zu disks after the edits, step %llu\n", world.diskCount(),
                    static_cast<unsigned long long>(world.stepCount()));

        // A scene file, its trajectory and statistics, and a checkpoint.
        carom::io::SceneFile file = carom::io::loadScene(argv[1]);
        carom::World mixture(file.world);
        mixture.setDisks(file.disks, argv[1]);
        carom::io::TrajectoryWriter trajectory("tour.xyz");
        carom::io::StatisticsWriter statistics("tour.csv");
        for (int sample = 0; sample < 5; ++sample) {
            trajectory.write(mixture);
            statistics.write(mixture);
            mixture.step(100);
        }
        trajectory.close();
        statistics.close();
        carom::io::saveCheckpoint("tour.ckpt", mixture);
        carom::io::writeState("tour-state.csv", mixture.disks());

        // The checkpoint continues bit for bit.
        carom::World resumed = carom::io::loadCheckpoint("tour.ckpt");
        mixture.step(100);
        resumed.step(100);
        std::vector<carom::Disk> a = mixture.disks(), b = resumed.disks();
        bool same = a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(carom::Disk)) == 0;
        std::printf("resumed from the checkpoint: %s\n", same ? "the same bits" : "DIFFERENT");
        return same ? 0 : 1;
    } catch (const carom::Error& e) {
        std::fprintf(stderr, "tour: %s\n", e.what());
        return 1;
    }
}
