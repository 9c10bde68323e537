// The README's C++ example, whole: a gas of 1000 disks, 1000 steps, and its
// energy, which the default (pairwise) collision scheme conserves to rounding.
#include <carom/carom.h>
#include <cstdio>

int main() {
    carom::SceneDef gas;  // 1000 disks of radius 1 and speed 1
    gas.packing = 0.5f;
    carom::Scene scene = carom::makeScene(gas);

    carom::WorldDef def;  // pairwise collisions on the CPU
    def.width = scene.width;
    def.height = scene.height;
    carom::World world(def);
    world.setDisks(scene.disks);
    world.step(1000);
    std::printf("kinetic energy %.9g (started at %.9g)\n", world.kineticEnergy(), 0.5 * scene.disks.size());
}
