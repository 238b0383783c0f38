"""Bounds on what a model file can make vimpact and the compiler do, through the command line:
each file below once crashed vimpact or took the machine's memory; each is now refused at once
with one line naming the key."""
import os
import resource
import subprocess
import time

import pytest

from conftest import TWO_SIDED_TOML


def limited_memory():
    # A model file that asks for gigabytes must be refused, not tried: the test caps what a
    # regression could take from the machine.
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


def vimpact_run(vimpact, cache, *args, env=None, cwd=None, timeout=300, memory_limit=False):
    e = dict(os.environ, VIMPACT_CACHE_DIR=str(cache))
    e.update(env or {})
    return subprocess.run([vimpact, *map(str, args)], capture_output=True, text=True, env=e, cwd=cwd, timeout=timeout,
                          preexec_fn=limited_memory if memory_limit else None)


def private_cache(tmp_path, name="cache"):
    d = tmp_path / name
    d.mkdir(mode=0o700)
    return d


def one_line_error(p):
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    return lines[0]


# ---- bounds on what a model file can make vimpact and the compiler do

def chain(links):
    """Named expressions that each use the one before twice: the written-out code doubles per link."""
    lines = ['e0 = "v + x"'] + [f'e{i} = "e{i - 1}^2 + sin(e{i - 1}) - x"' for i in range(1, links + 1)]
    return "\n".join(lines), f"e{links}"


@pytest.mark.parametrize("case", ["nesting", "constant", "chain"])
def test_a_model_file_that_would_exhaust_the_machine_is_refused_at_once(vimpact, tmp_path, case):
    text = open(TWO_SIDED_TOML).read()
    if case == "nesting":  # crashed GiNaC's parser (SIGSEGV)
        text = text.replace('x = "v"', 'x = "' + "(" * 8000 + "v" + ")" * 8000 + '"')
        needle = "derivatives.x: the expression nests more than 250 levels deep"
    elif case == "constant":  # asked for a number of 2^40 bits
        text = text.replace('x = "v"', 'x = "2^(2^40)*v"')
        needle = "derivatives.x: an exact constant of the expression would have more than 65536 bits"
    else:  # 118 MB of source at 14 links
        exprs, last = chain(14)
        text = text.replace("[derivatives]", "[expressions]\n" + exprs + "\n\n[derivatives]")
        text = text.replace('x = "v"', f'x = "{last}"')
        needle = "would make the generated code too large"
    path = tmp_path / "greedy.toml"
    path.write_text(text)
    cache = private_cache(tmp_path)
    start = time.monotonic()
    p = vimpact_run(vimpact, cache, "models", path, timeout=120, memory_limit=True)
    elapsed = time.monotonic() - start
    line = one_line_error(p)
    assert line.startswith(f"vimpact: error: model file {path}: ") and needle in line, line
    assert elapsed < 10.0
    assert os.listdir(cache) == []
