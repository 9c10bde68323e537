"""The ends of a world's counts, as Python meets them."""
import struct
import zlib

import pytest

import carom


def test_step_refuses_to_take_the_step_count_past_its_last_value(tmp_path):
    world = carom.World(box=(10, 10), dt=1.0)
    world.set_disks([[2, 2], [7, 6]], [[1, 0.5], [-1, 0]], [1, 1], [1, 1])
    world.step(20)
    path = tmp_path / "late.ckpt"
    world.save_checkpoint(path)
    data = bytearray(path.read_bytes())
    struct.pack_into("<Q", data, 48, 2**64 - 2)  # the step, after the header, box, dt, gravity and boundary
    data[-4:] = struct.pack("<I", zlib.crc32(bytes(data[:-4])))
    path.write_bytes(bytes(data))
    late = carom.World.from_checkpoint(path)
    assert late.step_count == 2**64 - 2
    with pytest.raises(carom.InputError, match=r"^step: 5 steps from step 18446744073709551614 would take the step "
                                               r"count past 2\^64 - 1; allowed: at most 1$"):
        late.step(5)
    assert late.step_count == 2**64 - 2
    late.step(1)
    assert late.step_count == 2**64 - 1
