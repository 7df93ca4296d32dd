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

import hygiene
from hygiene import c_tokens

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
    """(line, text) of each C string literal but an #include's (hygiene.c_tokens)."""
    out = []
    for kind, start, end, line in c_tokens(text):
        if kind != "string":
            continue
        line_start = text.rfind("\n", 0, start) + 1
        if text.startswith("#include", line_start):
            continue
        out.append((line, text[start + 1:end - 1] if text[end - 1] == '"' else text[start + 1:end]))
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
    return hygiene.main(argv, __doc__, check, self_test,
                        "%d core message(s) name a scene key or an option: name the "
                        "core's parameter, and map it in the scene or program layer",
                        "the core's messages name no scene key and no option")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
