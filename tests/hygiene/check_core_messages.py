#!/usr/bin/env python3
"""The core's messages name the core's own parameters (issue 24).

The core (src/core/, include/popc/core/) knows no scene and no command line:
a message it writes names its configuration's fields (mass_kg, period_s,
window_s), and the layer that made that configuration names them as its user
wrote them (popc_error_name_params: the scene layer's popc_plant_name_keys,
popc-analyze's ana_chatter_name_options). This test reads every string
literal of the core and refuses

  - a scene key, "section.key" for any key of the scene's one table
    (src/scene/scene.c, scene_keys[]: NUM("run", "rate", ...) and
    {"run", "delay_ticks", ...} rows), and
  - a command-line option, "--word".

Usage: check_core_messages.py SOURCE_ROOT    exit 0, or 1 listing file:line
       check_core_messages.py --self-test
"""
import glob
import os
import re
import sys
import tempfile

KEY_ROW = re.compile(r'(?:NUM\w*\(|\{)\s*"([a-z_]+)",\s*"([a-z_0-9]+)",')
# NUM_ADM("k", ...) rows carry their section in the macro
ADM_ROW = re.compile(r'NUM_ADM\(\s*"([a-z_0-9]+)",')
OPTION = re.compile(r"(?<![-\w])--[a-z][a-z-]*")


def scene_keys(root):
    with open(os.path.join(root, "src", "scene", "scene.c"), encoding="utf-8") as f:
        text = f.read()
    keys = {"%s.%s" % m.groups() for m in KEY_ROW.finditer(text)}
    keys |= {"admittance.%s" % m.group(1) for m in ADM_ROW.finditer(text)}
    return keys


def literals(text):
    """(line, text) of each C string literal, comments and chars skipped."""
    out = []
    i, n, line = 0, len(text), 1
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            line += text.count("\n", i, j)
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif c == "'":
            j = i + 1
            while j < n and text[j] != "'":
                j += 2 if text[j] == "\\" else 1
            i = j + 1
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"' and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append((line, text[i + 1:j]))
            i = j + 1
        elif text.startswith("#include", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        else:
            i += 1
    return out


def check(root):
    keys = scene_keys(root)
    if len(keys) < 20:
        return ["src/scene/scene.c: only %d scene keys read: the table's form "
                "changed, fix KEY_ROW" % len(keys)]
    key_re = re.compile(r"(?<![\w.])(?:" + "|".join(
        re.escape(k) for k in sorted(keys, key=len, reverse=True)) + r")(?![\w])")
    bad = []
    files = sorted(glob.glob(os.path.join(root, "src", "core", "*.[ch]")) +
                   glob.glob(os.path.join(root, "include", "popc", "core", "*.h")))
    for path in files:
        rel = os.path.relpath(path, root)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for line, lit in literals(text):
            for m in key_re.finditer(lit):
                bad.append("%s:%d: names the scene key %s" % (rel, line, m.group(0)))
            for m in OPTION.finditer(lit):
                bad.append("%s:%d: names the option %s" % (rel, line, m.group(0)))
    return bad


def self_test():
    with tempfile.TemporaryDirectory() as root:
        def put(rel, text):
            path = os.path.join(root, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w") as f:
                f.write(text)
        rows = "".join('\tNUM("operator", "k%d", x, "1", 0, 1, 0, "", ""),\n' % i
                       for i in range(20))
        put("src/scene/scene.c", rows + '\t{"run", "rate", KEY_INT,\n'
            '\tNUM_ADM("servo_damping", x),\n')
        put("src/core/a.c", '#include "popc/run.rate.h"\n'
            '/* run.rate, --set */ f("T = period_s, run.rates");\n'
            'g("raise run.rate"); h("use --threshold x", \'"\');\n'
            'k("admittance.servo_damping"); m("a--b -- x");\n')
        got = check(root)
        want = ["src/core/a.c:3: names the scene key run.rate",
                "src/core/a.c:3: names the option --threshold",
                "src/core/a.c:4: names the scene key admittance.servo_damping"]
        if got != want:
            print("self-test: got %s\nwant %s" % (got, want))
            return 1
    print("self-test: ok")
    return 0


def main(argv):
    if len(argv) == 2 and argv[1] == "--self-test":
        return self_test()
    if len(argv) != 2:
        print(__doc__.strip().split("\n\n")[-1], file=sys.stderr)
        return 2
    bad = check(argv[1])
    for b in bad:
        print(b)
    if bad:
        print("%d core message(s) name a scene key or an option: name the "
              "core's parameter, and map it in the scene or program layer" % len(bad))
        return 1
    print("the core's messages name no scene key and no option")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
