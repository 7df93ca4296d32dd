#!/usr/bin/env python3
"""Exit codes are written as the enum of include/popc/util/error.h (issue 24).

`return 2;` in a verb's function is the exit code POPC_EXIT_USAGE, and
README's exit-code table is that enum: a literal hides which code is meant
and cannot be found with the name. This test reads the programs' sources
(src/cli, src/servo_sim, analysis, and the programs' helpers) and refuses, in
every function, a literal 1 to 7

  - returned (`return 2;`), given to exit or _exit (`exit(1)`),
  - assigned to an exit-code variable (`rc = 2;`), or
  - chosen by a conditional that returns (`return x ? 1 : 0;`),

but in the functions of TRUTH, whose 1 is a truth value or a count, not an
exit code (each named with what it returns).

Usage: check_exit_literals.py SOURCE_ROOT    exit 0, or 1 listing file:line
       check_exit_literals.py --self-test
"""
import glob
import os
import re
import sys
import tempfile

import hygiene
from hygiene import c_tokens

FOLDERS = ("src/cli", "src/servo_sim", "analysis", "src/programs")
# (file, function): what its literal 1 means
TRUTH = {
    ("src/cli/bench_floor.c", "applies"): "whether the floor covers the scene",
    ("src/cli/cli_common.c", "popc_cli_set_names_key"): "whether a --set names the key",
    ("src/cli/cli_common.c", "popc_cli_stdout_closed"): "whether stdout was closed (caller exits 2)",
    ("src/cli/sweep_pool.c", "record_lost"): "trouble: a row could not be recorded",
    ("src/cli/sweep_pool.c", "worker_ended"): "trouble: a worker ended badly",
    ("src/cli/sweep_pool.c", "run_pool"): "trouble: the pool could not run",
    ("src/cli/sweep_pool.c", "pool_slots"): "a count of slots",
    ("src/servo_sim/servo_sim.c", "handle"): "whether the server is to stop",
    ("src/servo_sim/servo_sim.c", "wait_readable"): "whether the descriptor is readable",
    ("src/servo_sim/frame.c", "known_function"): "whether the function code is known",
    ("src/servo_sim/frame.c", "frame_request_ok"): "whether the request is whole",
    ("src/servo_sim/drive.c", "write_span"): "whether the span is in the map",
    ("analysis/log_names.c", "suffix_name"): "a count of path components",
    ("analysis/report_out.c", "report_log_has"): "whether the log has the figure's columns",
    ("analysis/common.c", "set_given"): "whether --set gave the key",
    ("analysis/common.c", "ana_log_next"): "1: a row, 0: the end",
    ("analysis/teleop_log.c", "ana_tele_next"): "1: a row, 0: the end",
    ("src/cli/bench_log.c", "child_read_rss_kib"): "a measuring child's status, 0 or 1, read by bench_log",
    ("src/cli/cli_common.c", "popc_cli_assignment_split"): "whether a value lacks its '=' (caller exits 2)",
    ("src/cli/sweep_dry_run.c", "sweep_dry_run_dir"): "whether the sweep would be refused",
    ("analysis/read_mat_check.c", "take_bytes"): "1: the compressed stream ended first",
    ("analysis/report_figures.c", "counts_range"): "whether there is a counts panel",
}

FUNC_START = re.compile(r"^(?:static\s+|inline\s+)*[A-Za-z_][\w\s\*]*?\b([A-Za-z_]\w*)\s*\(")
LITERAL = [
    re.compile(r"\breturn\s+[1-7]\s*;"),
    re.compile(r"\b_?exit\s*\(\s*[1-7]\s*\)"),
    re.compile(r"\b(?:rc|ret|code|exit_code|status)\s*=\s*[1-7]\s*;"),
    re.compile(r"\breturn\b[^;]*\?\s*[1-7]\s*:\s*[0-7]\s*;"),
    re.compile(r"\breturn\b[^;]*\?\s*[0-7]\s*:\s*[1-7]\s*;"),
    re.compile(r"\b_?exit\s*\([^;]*\?\s*[0-7]\s*:\s*[0-7]\s*\)"),
]


def strip_comments(text):
    """The text with comments blanked (newlines kept) and strings and
    character constants emptied (hygiene.c_tokens)."""
    out, at = [], 0
    for kind, start, end, _line in c_tokens(text):
        out.append(text[at:start])
        if kind == "comment":
            out.append(re.sub(r"[^\n]", " ", text[start:end]))
        else:
            out.append(text[start] * 2)
        at = end
    out.append(text[at:])
    return "".join(out)


def findings(root):
    for folder in FOLDERS:
        for path in sorted(glob.glob(os.path.join(root, folder, "*.c"))):
            rel = os.path.relpath(path, root)
            with open(path, encoding="utf-8") as f:
                text = strip_comments(f.read())
            func = None
            for k, row in enumerate(text.split("\n"), 1):
                if row and not row[0].isspace() and row[0] not in "#}{":
                    m = FUNC_START.match(row)
                    if m and not row.rstrip().endswith(";"):
                        func = m.group(1)
                if any(p.search(row) for p in LITERAL):
                    yield rel, k, func, row.strip()


def check(root):
    return ["%s:%d: in %s: %s" % (rel, k, func, row)
            for rel, k, func, row in findings(root) if (rel, func) not in TRUTH]


def self_test():
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "src", "cli"))
        with open(os.path.join(root, "src", "cli", "cmd_x.c"), "w") as f:
            f.write("int popc_cmd_x(int argc)\n{\n\tif (argc)\n\t\treturn 2;\n"
                    "\trc = 1; /* return 1; */\n\treturn argc ? 1 : 0;\n}\n"
                    "static int applies(int x)\n{\n\treturn 1;\n}\n"
                    "int main(void)\n{\n\texit(1);\n\treturn POPC_EXIT_USAGE;\n"
                    "\treturn 10; puts(\"return 1;\");\n}\n")
        got = check(root)
        want = ["src/cli/cmd_x.c:4: in popc_cmd_x: return 2;",
                "src/cli/cmd_x.c:5: in popc_cmd_x: rc = 1;",
                "src/cli/cmd_x.c:6: in popc_cmd_x: return argc ? 1 : 0;",
                "src/cli/cmd_x.c:10: in applies: return 1;",
                "src/cli/cmd_x.c:14: in main: exit(1);"]
        if got != want:
            print("self-test: got\n  %s\nwant\n  %s" % ("\n  ".join(got), "\n  ".join(want)))
            return 1
    print("self-test: ok")
    return 0


def main(argv):
    return hygiene.main(argv, __doc__, check, self_test,
                        "%d exit code(s) written as a number: use enum popc_exit "
                        "(include/popc/util/error.h), or add a truth-valued function to "
                        "TRUTH with what its 1 means",
                        "every exit code is named")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
