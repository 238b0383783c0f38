"""The compiled-model cache from Python: Ctrl-C while a model file compiles stops it at once
(KeyboardInterrupt, the compiler ended, nothing left in the cache), and a damaged entry is
compiled again instead of crashing the interpreter. Each case runs in an interpreter of its own,
which receives the signal or loads the damaged entry."""
import os
import re
import signal
import subprocess
import sys
import time

import pytest

from conftest import TWO_SIDED_TOML

ENTRY = re.compile(r"^two_sided_impact_oscillator-[0-9a-f]+\.so$")


def python(code, cache, **env):
    return subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ, VIMPACT_CACHE_DIR=str(cache), **env))


def runs(pid):
    """Whether a process runs (a zombie has ended)."""
    try:
        stat = open(f"/proc/{pid}/stat").read()
    except FileNotFoundError:
        return False
    return stat[stat.rindex(")") + 2] != "Z"


LOADS = {
    "from_file": f"vimpact.Model.from_file({TWO_SIDED_TOML!r})",
    "from_toml": f"vimpact.Model.from_toml(open({TWO_SIDED_TOML!r}).read())",
    "constructor": f"vimpact.Model({TWO_SIDED_TOML!r})",
}


@pytest.mark.parametrize("load", sorted(LOADS))
def test_ctrl_c_while_a_model_compiles_stops_it_at_once(tmp_path, load):
    cache = tmp_path / "cache"
    cache.mkdir(mode=0o700)
    pid_file = tmp_path / "compiler.pid"
    script = tmp_path / "sleeping-c++"
    script.write_text(f"#!/bin/sh\necho $$ > '{pid_file}.tmp'\nmv '{pid_file}.tmp' '{pid_file}'\nsleep 60\n")
    script.chmod(0o755)
    proc = python(f"import vimpact\n{LOADS[load]}\n", cache, CXX=str(script))
    for _ in range(6000):
        if pid_file.exists() or proc.poll() is not None:
            break
        time.sleep(0.01)
    assert pid_file.exists(), proc.communicate()
    compiler = int(pid_file.read_text())
    start = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=20)
    finally:
        if runs(compiler):
            os.kill(compiler, signal.SIGKILL)
        if proc.poll() is None:
            proc.kill()
    elapsed = time.monotonic() - start
    assert err.strip().splitlines()[-1] == "KeyboardInterrupt", err
    assert elapsed < 2.0
    assert not runs(compiler)
    assert os.listdir(cache) == []


def test_a_truncated_entry_is_compiled_again_not_a_crash(tmp_path):
    cache = tmp_path / "cache"
    cache.mkdir(mode=0o700)
    rhs = f"import vimpact\nprint(list(vimpact.Model.from_file({TWO_SIDED_TOML!r}).rhs([0.5, -0.25, 0.0])))\n"
    first = python(rhs, cache)
    out, err = first.communicate(timeout=300)
    assert first.returncode == 0, err
    # x' = v, v' = -2 zeta v - x + a cos(phi), phi' = w at the defaults zeta 0.05, a 1, w 1.2
    assert eval(out) == pytest.approx([-0.25, -2 * 0.05 * -0.25 - 0.5 + 1.0, 1.2], rel=1e-15)
    [so] = [f for f in os.listdir(cache) if ENTRY.match(f)]
    os.truncate(cache / so, os.path.getsize(cache / so) // 2)  # SIGBUS in every interpreter that loaded it
    again = python(rhs, cache)
    out2, err2 = again.communicate(timeout=300)
    assert again.returncode == 0, err2
    assert out2 == out
