#!/usr/bin/env python3
"""The public headers, as their include names (popc/<layer>/x.h), one a line.

    list_headers.py INCLUDE_DIR                  print them (meson reads this at configure time)
    list_headers.py INCLUDE_DIR --expect H...    exit 1 unless they are exactly H...

The second form is the test 'headers-listed': the build compiles the headers
meson saw when it was configured, so a header added since then would not be
checked until 'meson setup --reconfigure'; the test says so.
"""
import os
import sys


def headers(include_dir):
    found = []
    for dirpath, dirnames, filenames in os.walk(include_dir):
        dirnames.sort()
        for name in filenames:
            if name.endswith(".h"):
                rel = os.path.relpath(os.path.join(dirpath, name), include_dir)
                found.append(rel.replace(os.sep, "/"))
    return sorted(found)


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    now = headers(argv[1])
    if len(argv) == 2:
        print("\n".join(now))
        return 0
    if argv[2] != "--expect":
        print(__doc__, file=sys.stderr)
        return 2
    configured = sorted(argv[3:])
    if now == configured:
        print(f"{len(now)} public headers, each compiled on its own by the build")
        return 0
    for h in sorted(set(now) - set(configured)):
        print(f"include/{h}: not compiled on its own: added after meson was configured")
    for h in sorted(set(configured) - set(now)):
        print(f"include/{h}: gone since meson was configured")
    print("run: meson setup --reconfigure BUILDDIR")
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
