#!/usr/bin/env python3
"""Nothing in the library prints, exits or reads the environment (issue 24).

libpopc.a holds every object the library is made of (src/lib and the layers
util .. run it links whole; src/lib/meson.build). A device loop links it
into a process that owns its terminal, its exit and its environment, so no
object may call or name:

  - the standard streams or what writes to them (stdout, stderr, printf,
    puts, perror, ...): output goes to a FILE or descriptor the caller gives
    (fprintf on it is fine: without stdout/stderr it cannot be a standard
    stream), a message into a popc_error;
  - exit, abort, assert's __assert_fail: an error is a negative status;
  - getenv and its kin, getopt's globals: settings come from arguments.

`nm -u` of each archive member lists what it needs from outside; a name
below that is not in ALLOWED (member, symbol) with its reason fails.

Usage: check_library_calls.py NM LIBPOPC_A   exit 0, or 1 listing member: symbol
       check_library_calls.py --self-test NM CC
"""
import os
import subprocess
import sys
import tempfile

FORBIDDEN = {
    # printing: the standard streams and the calls that write to them
    "stdout", "stderr", "printf", "vprintf", "puts", "putchar", "perror",
    "psignal", "__printf_chk", "__vprintf_chk", "error", "error_at_line",
    "err", "errx", "warn", "warnx", "verr", "verrx", "vwarn", "vwarnx",
    "syslog", "vsyslog",
    # exiting
    "exit", "_exit", "_Exit", "quick_exit", "abort", "__assert_fail",
    "__assert_perror_fail", "atexit", "raise", "kill",
    # the environment and the command line
    "getenv", "secure_getenv", "__secure_getenv", "setenv", "unsetenv",
    "putenv", "clearenv", "environ", "__environ", "optind", "optopt",
    "optarg", "opterr", "getopt", "getopt_long", "system", "popen",
}

# (archive member, symbol): why it stays. Keep it short; each entry is a debt
# or a caller's explicit request.
ALLOWED = {
    ("log_writer.c.o", "stdout"):
        "the path '-' is the caller's request to write the log to standard "
        "output (popc run --log -): stdio's pending text is flushed first",
    ("log_reader.c.o", "stdin"):
        "the path '-' is the caller's request to read standard input",
}


def undefined(nm, archive):
    """{(member, symbol)} of the archive's undefined symbols."""
    out = subprocess.run([nm, "-A", "-u", archive], check=True,
                         capture_output=True, text=True).stdout
    found = set()
    for row in out.splitlines():
        # "archive:member:                 U symbol"
        head, _, sym = row.rpartition(" ")
        member = head.split(":")[1] if head.count(":") >= 2 else head.split(":")[0]
        found.add((member.strip(), sym.split("@")[0]))
    return found


def check(nm, archive):
    bad = []
    for member, sym in sorted(undefined(nm, archive)):
        if sym in FORBIDDEN and (member, sym) not in ALLOWED:
            bad.append("%s: %s" % (member, sym))
    return bad


def self_test(nm, cc):
    with tempfile.TemporaryDirectory() as d:
        srcs = {
            "good.c": "#include <stdio.h>\nint g(FILE *f) { return fprintf(f, \"x\"); }\n",
            "bad.c": "#include <stdio.h>\n#include <stdlib.h>\n"
                     "int b(void) { if (getenv(\"X\")) abort(); "
                     "return fprintf(stderr, \"x\"); }\n",
        }
        objs = []
        for name, text in srcs.items():
            with open(os.path.join(d, name), "w") as f:
                f.write(text)
            obj = os.path.join(d, name + ".o")
            subprocess.run([cc, "-c", "-O1", "-o", obj, os.path.join(d, name)], check=True)
            objs.append(obj)
        ar = os.path.join(d, "libx.a")
        subprocess.run(["ar", "rc", ar] + objs, check=True)
        got = check(nm, ar)
        want = ["bad.c.o: abort", "bad.c.o: getenv", "bad.c.o: stderr"]
        if got != want:
            print("self-test: got %s, want %s" % (got, want))
            return 1
    print("self-test: ok")
    return 0


def main(argv):
    if len(argv) == 4 and argv[1] == "--self-test":
        return self_test(argv[2], argv[3])
    if len(argv) != 3:
        print(__doc__.strip().split("\n\n")[-1], file=sys.stderr)
        return 2
    bad = check(argv[1], argv[2])
    for b in bad:
        print(b)
    if bad:
        print("%d call(s) of the library print, exit or read the environment "
              "(tests/hygiene/check_library_calls.py says what to do instead)" % len(bad))
        return 1
    print("the library neither prints nor exits nor reads the environment "
          "(%d allowed, with reasons)" % len(ALLOWED))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
