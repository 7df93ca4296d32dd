#!/usr/bin/env python3
"""A device loop in Python: libpopc's port stepped tick by tick against the
simulated device, the rows kept in numpy arrays, then checked against
`popc run`'s log of the same scene (popc.run): equal bit for bit.

    step_controller.py SCENE [VARIANT]      exit 0 when every cell is equal
"""
import sys

import numpy

import popc


def main(argv):
    scene = popc.Scene(argv[1] if len(argv) > 1 else "paper")
    if len(argv) > 2:
        scene.set("controller.variant", argv[2])
    port, device = popc.Port(scene), popc.Sim(scene)
    n = scene.tick_count
    f_c = numpy.empty(n)
    W = numpy.empty(n)
    x_true = numpy.empty(n)
    for k in range(n):
        sample = device.sample           # the device: a count
        tick = port.step(sample.count)   # the controller: a force
        f_c[k], W[k], x_true[k] = tick.f_c_N, tick.W_J, sample.x_true_m
        if k + 1 < n:
            device.exchange(tick.f_c_N)
    log = popc.run(scene)                # the same scene, as popc run
    same = all(numpy.array_equal(a.view(numpy.uint64), log.rows[c].view(numpy.uint64))
               for a, c in ((f_c, "f_c"), (W, "W"), (x_true, "x_true")))
    print("%d ticks of %s: f_c, W and x_true %s popc run's log, bit for bit"
          % (n, log.header["variant"], "equal" if same else "DIFFER FROM"))
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
