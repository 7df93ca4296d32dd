#!/usr/bin/env python3
"""Reading a popc log: the header as a dict, the rows as a numpy structured
array (and a pandas DataFrame when pandas is installed), W recomputed from
the rows with the library's observer, as popc-analyze energy does.

    read_log.py LOG       exit 0 when the recomputed W equals the logged W bit for bit
"""
import sys

import numpy

import popc


def main(argv):
    log = popc.read_log(argv[1])
    print("variant %s, %d rows, stop: %s" % (log.header["variant"], len(log.rows), log.stop))
    # the scene of the log, from its header: the observer of its variant
    scene = popc.Scene()
    for key, value in log.header.items():
        if "." in key and not key.startswith("axis."):
            scene.set(key, value)
    observer = popc.Observer(scene)
    W = numpy.empty(len(log.rows))
    for i, row in enumerate(log.rows):
        t = popc.Tick(x_m=row["x"], count=int(row["count"]), v_mps=row["v"], f_e_N=row["f_e"],
                      f_c_N=row["f_c"])
        W[i], _ = observer.step(t)
    same = numpy.array_equal(W.view(numpy.uint64), log.rows["W"].view(numpy.uint64))
    print("W recomputed: %s the log's, bit for bit" % ("equal to" if same else "DIFFERENT FROM"))
    try:
        frame = log.dataframe()
        print("pandas: %d rows, f_c RMS %.6g N" % (len(frame), float(numpy.sqrt((frame["f_c"] ** 2).mean()))))
    except ImportError:
        print("pandas: not installed, no DataFrame")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
