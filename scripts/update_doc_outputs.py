"""Re-runs every command shown in a document and puts its real output under it, so the
numbers in README.md and docs/*.md are always those of the current build; with --check,
changes nothing and fails (exit 1, with a diff) when a document disagrees with its commands.

A command is an indented line `$ COMMAND` (environment assignments may precede the program);
its output is the indented block that follows, up to an empty line or the next command (a
blank line of the output is written as the indentation alone).
Markers at the end of a command line, after two spaces and `#`:
  - a comment that mentions Ctrl-C: the output is a recording (an interruption cannot be
    replayed); never re-run;
  - `# varies`: the output depends on the machine (timings); re-run by an update, not
    compared by --check.

Usage (from the repository root, after building):
  /usr/bin/python3 scripts/update_doc_outputs.py [--check] [FILE ...]   (default: README.md)"""
import difflib
import os
import re
import shlex
import subprocess
import sys


def run(cmd):
    env = dict(os.environ)
    argv = shlex.split(cmd)
    while argv and re.fullmatch(r"[A-Z_]+=\S*", argv[0]):
        k, v = argv.pop(0).split("=", 1)
        env[k] = v
    p = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=900)
    text = (p.stdout + p.stderr).rstrip("\n")
    return text.split("\n") if text.strip() else []


def process(path, check):
    lines = open(path).read().split("\n")
    out, i, differences = [], 0, []
    while i < len(lines):
        line = lines[i]
        m = re.match(r"^(\s+)\$ (.*)$", line)
        if not m:
            out.append(line)
            i += 1
            continue
        indent, cmd = m.group(1), m.group(2)
        out.append(line)
        i += 1
        old = []
        while i < len(lines) and lines[i] and lines[i].startswith(indent) and not re.match(r"^\s+\$ ", lines[i]):
            old.append(lines[i])
            i += 1
        comment = cmd.split("  #", 1)[1] if "  #" in cmd else ""
        if "Ctrl-C" in comment:
            out.extend(old)
            continue
        cmd = cmd.split("  #")[0].strip()
        new = [indent + x for x in run(cmd)]
        if old != new and not (check and "varies" in comment):
            differences.append((cmd, old, new))
        out.extend(new)
    if check:
        for cmd, old, new in differences:
            print(f"{path}: the output of `{cmd}` differs from the document:", file=sys.stderr)
            sys.stderr.writelines(x + "\n" for x in difflib.unified_diff(old, new, "document", "command", lineterm=""))
    else:
        for cmd, _, _ in differences:
            print(f"{path}: updated: {cmd}", file=sys.stderr)
        text = "\n".join(out)
        open(path, "w").write(text if text.endswith("\n") else text + "\n")
    return not differences


def main():
    args = sys.argv[1:]
    check = "--check" in args
    files = [a for a in args if a != "--check"] or ["README.md"]
    ok = all([process(f, check) for f in files])
    sys.exit(0 if ok or not check else 1)


if __name__ == "__main__":
    main()
