#!/usr/bin/env python3
"""The seed corpus of fuzz_cli: the lgvi-testbed commands the README and the docs show, as
argument vectors (one argument a line, the program name left out), one file per distinct command.

Usage: cli_seeds.py OUT_DIR FILE.md...   (tests/sanitize.sh: README.md docs/*.md experiments/*/README.md)

A command is the text after "lgvi-testbed " on a line of a code block or inside `...`, up to a
shell operator (&&, ||, |, ;) or a comment; shell words as the shell would split them (a command
the shell cannot split is split at blanks). Placeholders (SCENE, [--out DIR]) stay as written:
they are seeds for the refusals.
"""
import hashlib
import os
import re
import shlex
import sys

COMMAND = re.compile(r"(?:^|[\s`(])(?:\./)?(?:[\w.-]+/)*lgvi-testbed((?:\s[^`\n]*)?)")


def commands(text):
    for match in COMMAND.finditer(text):
        rest = match.group(1)
        for stop in ("&&", "||", "|", ";", " # ", "\t#"):
            if stop in rest:
                rest = rest[: rest.index(stop)]
        rest = rest.strip().rstrip("\\").strip()
        try:
            words = shlex.split(rest, comments=False)
        except ValueError:
            words = rest.split()
        yield words


def main():
    out_dir = sys.argv[1]
    os.makedirs(out_dir, exist_ok=True)
    seen = set()
    for path in sys.argv[2:]:
        with open(path, encoding="utf-8") as f:
            for words in commands(f.read()):
                data = "\n".join(words)
                if data in seen:
                    continue
                seen.add(data)
                name = hashlib.sha1(data.encode()).hexdigest()[:16]
                with open(os.path.join(out_dir, "cli-" + name), "w", encoding="utf-8") as f:
                    f.write(data)
    print("cli_seeds.py: %d argument vectors" % len(seen))


if __name__ == "__main__":
    main()
