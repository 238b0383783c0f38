"""Re-runs every `$ build/vimpact ...` and `$ PYTHONPATH=... ` command shown in README.md and
puts its real output under it, so the README's numbers are always those of the current build.

Usage (from the repository root, after building): /usr/bin/python3 scripts/update_readme_outputs.py
A command line ending in a `# ...` comment that mentions Ctrl-C is shown with its recorded
output (an interruption cannot be replayed)."""
import os
import re
import shlex
import subprocess
import sys

README = "README.md"


def run(cmd):
    env = dict(os.environ)
    argv = shlex.split(cmd)
    while argv and re.fullmatch(r"[A-Z_]+=\S*", argv[0]):
        k, v = argv.pop(0).split("=", 1)
        env[k] = v
    p = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=900)
    return (p.stdout + p.stderr).rstrip("\n").split("\n") if (p.stdout + p.stderr).strip() else []


def main():
    lines = open(README).read().split("\n")
    out, i = [], 0
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
        while i < len(lines) and lines[i].startswith(indent) and not re.match(r"^\s+\$ ", lines[i]) and lines[i].strip():
            old.append(lines[i])
            i += 1
        if "Ctrl-C" in cmd:
            out.extend(old)
            continue
        cmd = cmd.split("  #")[0].strip()
        new = run(cmd)
        out.extend(indent + x for x in new)
        if old != [indent + x for x in new]:
            print(f"updated: {cmd}", file=sys.stderr)
    open(README, "w").write("\n".join(out))


if __name__ == "__main__":
    main()
