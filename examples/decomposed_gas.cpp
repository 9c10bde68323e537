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
        def.decomposition = carom::makeDecomposition({MPI_COMM_WORLD});
        carom::World world(def);
        world.setDisks(scene.disks);
        world.step(200);
        // world.kineticEnergy() is the whole world's, the same on every process
        int rank = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        const carom::Disk first = world.disks()[0];
        if (rank == 0)
            std::printf("kinetic energy %.17g, %llu collisions, disk 0 at (%.9g, %.9g)\n", world.kineticEnergy(),
                        static_cast<unsigned long long>(world.collisionCount()), first.position.x, first.position.y);
    }
    MPI_Finalize();
}
