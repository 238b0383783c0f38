"""The compiled-model cache and the compiler's process, through the command line: a private
cache whose entries are checked before they are loaded (planted, truncated, swapped and foreign
entries), Ctrl-C and SIGKILL while a model compiles, and bounds on what a model file can make
vimpact and the compiler do."""
import json
import os
import re
import resource
import shutil
import signal
import subprocess
import time

import pytest

from conftest import TWO_SIDED_TOML

ENTRY = re.compile(r"^(?P<name>\w+?)-[0-9a-f]{16,64}\.(?P<ext>so|sha256|cpp)$")


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


def entry(cache, name, ext="so"):
    found = [f for f in os.listdir(cache) if (m := ENTRY.match(f)) and m["name"] == name and m["ext"] == ext]
    assert len(found) == 1, (name, ext, os.listdir(cache))
    return cache / found[0]


def temporaries(cache):
    return [f for f in os.listdir(cache) if ".tmp-" in f]


def shifted_model(tmp_path, name, shift):
    """The two-stop oscillator as a model of its own, with its forcing shifted: other results."""
    text = open(TWO_SIDED_TOML).read()
    text = text.replace('name = "two_sided_impact_oscillator"', f'name = "{name}"')
    text = text.replace('v = "-2*zeta*v - x + a*cos(phi)"', f'v = "-2*zeta*v - x + a*cos(phi) + {shift}"')
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def replace_file(target, source):
    """A copy renamed over the target (cp to a temporary, then mv)."""
    tmp = str(target) + ".replacing"
    shutil.copyfile(source, tmp)
    os.chmod(tmp, 0o600)
    os.rename(tmp, target)


def period(vimpact, cache, model):
    p = vimpact_run(vimpact, cache, "period", "--model", model, "--json")
    assert p.returncode == 0, p.stderr
    return p.stdout


@pytest.fixture(scope="session")
def compiled(vimpact, tmp_path_factory):
    """Two models compiled once into a cache of their own, and their results: each test that
    damages an entry starts from a copy of it, a private cache whose entries vimpact wrote
    (compiling the same models again in every test cost a minute)."""
    tmp = tmp_path_factory.mktemp("compiled")
    cache = private_cache(tmp)
    models = {name: shifted_model(tmp, name, shift) for name, shift in (("copied_a", 0.0), ("copied_b", 0.5))}
    return cache, models, {name: period(vimpact, cache, model) for name, model in models.items()}


def copy_of(compiled, tmp_path):
    cache = tmp_path / "cache"
    shutil.copytree(compiled[0], cache)
    assert os.stat(cache).st_mode & 0o777 == 0o700
    return cache


def one_line_error(p):
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    return lines[0]


# ---- entries checked before they are loaded

def test_a_planted_library_never_runs(vimpact, tmp_path, compiled):
    cache = copy_of(compiled, tmp_path)
    model = compiled[1]["copied_b"]
    marker = tmp_path / "marker"
    src = tmp_path / "planted.cpp"
    src.write_text('#include <cstdio>\n__attribute__((constructor)) static void planted() {\n'
                   f'    if (FILE* f = std::fopen("{marker}", "w")) {{ std::fputs("ran", f); std::fclose(f); }}\n}}\n')
    lib = tmp_path / "planted.so"
    subprocess.run(["c++", "-shared", "-fPIC", "-o", str(lib), str(src)], check=True)
    replace_file(entry(cache, "copied_b"), lib)
    p = vimpact_run(vimpact, cache, "models", model, "--json")
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["models"][0]["name"] == "copied_b"
    assert not marker.exists()


def test_a_truncated_entry_is_compiled_again(vimpact, tmp_path, compiled):
    cache = copy_of(compiled, tmp_path)
    so = entry(cache, "copied_b")
    size = so.stat().st_size
    os.truncate(so, size // 2)  # crashed every run with SIGBUS
    assert period(vimpact, cache, compiled[1]["copied_b"]) == compiled[2]["copied_b"]
    assert entry(cache, "copied_b").stat().st_size == size


@pytest.mark.parametrize("with_record", [False, True])
def test_an_entry_copied_over_another_models_is_not_run_in_its_place(vimpact, tmp_path, compiled, with_record):
    cache = copy_of(compiled, tmp_path)
    _, models, expected = compiled
    assert expected["copied_a"] != expected["copied_b"]  # the two models differ
    replace_file(entry(cache, "copied_b"), entry(cache, "copied_a"))
    if with_record:
        replace_file(entry(cache, "copied_b", "sha256"), entry(cache, "copied_a", "sha256"))
    assert period(vimpact, cache, models["copied_b"]) == expected["copied_b"]


@pytest.mark.parametrize("mode", [0o777, 0o770])
def test_a_cache_others_can_write_is_refused(vimpact, tmp_path, mode):
    cache = private_cache(tmp_path)
    os.chmod(cache, mode)
    line = one_line_error(vimpact_run(vimpact, cache, "models", TWO_SIDED_TOML))
    assert line == (f"vimpact: error: model file {TWO_SIDED_TOML}: the model cache directory {cache} is writable by "
                    f"other users (mode {mode:04o}), who could plant code in it: make it private (chmod 700 {cache}) or "
                    "set VIMPACT_CACHE_DIR")
    assert os.listdir(cache) == []


@pytest.mark.skipif(os.geteuid() != 0, reason="only root can give a file to another user")
def test_an_entry_of_another_user_is_refused(vimpact, tmp_path):
    cache = private_cache(tmp_path)
    model = shifted_model(tmp_path, "foreign", 0.5)
    assert vimpact_run(vimpact, cache, "models", model).returncode == 0
    so = entry(cache, "foreign")
    os.chown(so, 65534, 65534)
    line = one_line_error(vimpact_run(vimpact, cache, "models", model))
    assert line == (f"vimpact: error: model file {model}: the model cache entry {so} belongs to another user (uid "
                    "65534), so it is not loaded: remove it (the cache holds only your own files)")


def test_a_new_cache_is_private(vimpact, tmp_path):
    cache = tmp_path / "new" / "cache"
    assert vimpact_run(vimpact, cache, "models", TWO_SIDED_TOML).returncode == 0
    assert (cache.parent.stat().st_mode & 0o777, cache.stat().st_mode & 0o777) == (0o700, 0o700)
    for ext in ("so", "sha256", "cpp"):
        assert entry(cache, "two_sided_impact_oscillator", ext).stat().st_mode & 0o777 == 0o600


def test_a_relative_cache_that_looks_like_an_option(vimpact, tmp_path):
    # "-odd/NAME.cpp" reached the compiler, which took it for an option.
    p = vimpact_run(vimpact, "-odd", "models", TWO_SIDED_TOML, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    entry(tmp_path / "-odd", "two_sided_impact_oscillator")


def test_a_compiler_that_writes_no_library_is_named(vimpact, tmp_path):
    cache = private_cache(tmp_path)
    script = tmp_path / "garbage-c++"
    script.write_text('#!/bin/sh\nwhile [ $# -gt 0 ]; do\n  if [ "$1" = -o ]; then shift; echo garbage > "$1"; fi\n'
                      '  shift\ndone\nexit 0\n')
    script.chmod(0o755)
    line = one_line_error(vimpact_run(vimpact, cache, "models", TWO_SIDED_TOML, env={"CXX": str(script)}))
    assert line == (f"vimpact: error: model file {TWO_SIDED_TOML}: the C++ compiler {script} did not produce a loadable "
                    "shared library (it wrote a file that is not an ELF shared object; CXX selects the compiler)")
    assert os.listdir(cache) == []


def test_processes_compiling_the_same_model_at_once_all_succeed(vimpact, tmp_path):
    cache = private_cache(tmp_path)
    env = dict(os.environ, VIMPACT_CACHE_DIR=str(cache))
    procs = [subprocess.Popen([vimpact, "models", TWO_SIDED_TOML, "--json"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, env=env) for _ in range(3)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert [p.returncode for p in procs] == [0, 0, 0], [e for _, e in outs]
    assert outs[0][0] == outs[1][0] == outs[2][0]
    so = entry(cache, "two_sided_impact_oscillator")
    assert temporaries(cache) == []
    # Another run loads the entry: nothing is compiled or written again.
    before = so.stat().st_mtime_ns
    assert vimpact_run(vimpact, cache, "models", TWO_SIDED_TOML).returncode == 0
    assert so.stat().st_mtime_ns == before


# ---- Ctrl-C and SIGKILL while a model compiles

def sleeping_compiler(tmp_path):
    """A compiler that writes its pid and sleeps, with a child of its own (as g++ has)."""
    pid_file = tmp_path / "compiler.pid"
    script = tmp_path / "sleeping-c++"
    script.write_text(f"#!/bin/sh\necho $$ > '{pid_file}.tmp'\nmv '{pid_file}.tmp' '{pid_file}'\nsleep 60\n")
    script.chmod(0o755)
    return script, pid_file


def wait_for_pid(pid_file, proc):
    for _ in range(6000):
        if pid_file.exists():
            return int(pid_file.read_text())
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.01)
    raise AssertionError("the compiler did not start")


def runs(pid):
    """Whether a process runs (a zombie has ended)."""
    try:
        stat = open(f"/proc/{pid}/stat").read()
    except FileNotFoundError:
        return False
    return stat[stat.rindex(")") + 2] != "Z"


def ended_within(pid, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if not runs(pid):
            return True
        time.sleep(0.01)
    return False


def test_ctrl_c_while_a_model_compiles_stops_at_once_and_leaves_nothing(vimpact, tmp_path):
    cache = private_cache(tmp_path)
    script, pid_file = sleeping_compiler(tmp_path)
    proc = subprocess.Popen([vimpact, "models", TWO_SIDED_TOML], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=dict(os.environ, VIMPACT_CACHE_DIR=str(cache), CXX=str(script)))
    compiler = wait_for_pid(pid_file, proc)
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
    assert proc.returncode == 130, err
    assert err.strip() == "vimpact: interrupted; nothing written"
    assert elapsed < 2.0
    assert not runs(compiler)
    assert os.listdir(cache) == []


def test_a_killed_vimpact_takes_its_compiler_with_it(vimpact, tmp_path):
    cache = private_cache(tmp_path)
    script, pid_file = sleeping_compiler(tmp_path)
    proc = subprocess.Popen([vimpact, "models", TWO_SIDED_TOML], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=dict(os.environ, VIMPACT_CACHE_DIR=str(cache), CXX=str(script)))
    compiler = wait_for_pid(pid_file, proc)
    proc.kill()
    proc.communicate(timeout=20)
    try:
        assert ended_within(compiler, 3.0)
    finally:
        if runs(compiler):
            os.kill(compiler, signal.SIGKILL)
    assert temporaries(cache)  # what the killed process could not remove: the next compilation does
    model = shifted_model(tmp_path, "after_the_kill", 0.5)
    assert vimpact_run(vimpact, cache, "models", model).returncode == 0
    assert temporaries(cache) == []


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
