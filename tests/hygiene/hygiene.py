"""What the hygiene checks of tests/hygiene share: one C scanner and one
command line.

c_tokens is the scanner each check reads C through (check_paths.py: the
comments; check_core_messages.py: the string literals; check_exit_literals.py:
the code with comments blanked and strings emptied), so a rule about what a
comment or a string is holds for all of them at once.
"""
import sys


def c_tokens(text):
    """(kind, start, end, line) of each comment ("comment"), string literal
    ("string", quotes included) and character constant ("char") of C text, in
    order: text[start:end] is the token, line the 1-based line it starts on.
    A string or character constant ends at its closing quote or, unclosed,
    at the end of its line (the line end then belongs to it)."""
    i, n, line = 0, len(text), 1
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            yield ("comment", i, j, line)
            line += text.count("\n", i, j)
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            yield ("comment", i, j, line)
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            yield ("string" if c == '"' else "char", i, min(j + 1, n), line)
            i = j + 1
        else:
            i += 1


def main(argv, doc, check, self_test, failed, passed):
    """The command line of a check: ROOT, or --self-test. Prints each finding,
    then failed % count (exit 1), or passed (exit 0); exit 2 on bad usage."""
    if len(argv) == 2 and argv[1] == "--self-test":
        return self_test()
    if len(argv) != 2:
        print(doc.strip().split("\n\n")[-1], file=sys.stderr)
        return 2
    bad = check(argv[1])
    for b in bad:
        print(b)
    if bad:
        print(failed % len(bad))
        return 1
    print(passed)
    return 0
