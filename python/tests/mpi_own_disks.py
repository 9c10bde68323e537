"""Run by test_mpi.py under mpirun: a world that gathers on request. Between
steps each process reads its own disks, and the whole world's reads are
refused until gather(). Every process writes what it read.

    python mpi_own_disks.py OUT
"""
import json
import sys

from mpi4py import MPI

import carom

STEPS = 100


def whole(world):
    return {"positions": world.positions.tobytes().hex(), "images": world.images.tobytes().hex(),
            "kinetic_energy": world.kinetic_energy, "collisions": world.collisions}


def main(out):
    comm = MPI.COMM_WORLD
    world = carom.World((40.0, 30.0), boundary="periodic", dt=0.01, seed=5, comm=comm, gather="on_request")
    world.place(600, radius=(0.25, 0.5), mass=(1.0, 3.0), speed=2.0)
    world.step(STEPS)
    own = world.own_disks()
    try:
        world.kinetic_energy
        refused = ""
    except carom.Error as error:
        refused = str(error)
    world.gather()
    first = whole(world)
    world.step(STEPS)
    world.gather()
    read = {"ids": own.ids.tolist(), "positions": own.positions.tobytes().hex(),
            "velocities": own.velocities.tobytes().hex(), "images": own.images.tobytes().hex(),
            "refused": refused, "first": first, "second": whole(world), "device": world.device_name}
    with open(f"{out}.rank{comm.Get_rank()}.json", "w") as file:
        json.dump(read, file)


if __name__ == "__main__":
    main(*sys.argv[1:])
