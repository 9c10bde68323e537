// A world split among MPI processes (carom/decomposition.h): run it with
// `mpirun -np 4 decomposed_gas`. Every process prints the same numbers, which
// are those of one process, bit for bit, whatever the number of processes.
#include <carom/carom.h>
#include <carom/decomposition.h>

#include <cstdio>

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    {
        carom::SceneDef gas;  // the same disks on every process
        gas.particles = 4000;
        gas.packing = 0.5f;
        carom::Scene scene = carom::makeScene(gas);
        carom::WorldDef def;
        def.width = scene.width;
        def.height = scene.height;
        // The whole world comes to every process only when asked (world.gather()).
        def.decomposition = carom::makeDecomposition({MPI_COMM_WORLD, 0, 0, carom::Gather::OnRequest});
        carom::World world(def);
        world.setDisks(scene.disks);
        int rank = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        for (int chunk = 0; chunk < 4; ++chunk) {
            world.step(50);
            // Between steps each process reads the disks in its own domain.
            unsigned long long own = world.ownDisks().ids.size(), all = 0;
            MPI_Reduce(&own, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
            if (rank == 0) std::printf("step %llu: %llu disks among the processes\n", 50ull * (chunk + 1), all);
        }
        world.gather();  // collective: world.kineticEnergy() is now the whole world's, the same on every process
        const carom::Disk first = world.disks()[0];
        if (rank == 0)
            std::printf("kinetic energy %.17g, %llu collisions, disk 0 at (%.9g, %.9g)\n", world.kineticEnergy(),
                        static_cast<unsigned long long>(world.collisionCount()), first.position.x, first.position.y);
    }
    MPI_Finalize();
}
