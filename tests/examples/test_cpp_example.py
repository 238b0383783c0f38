"""The user-model example (examples/cpp): an impact damper written as a C++ definition with
automatic derivatives, run by its own program, loaded as a plugin by the command line and by
Python, and built on its own against an installed vimpact (find_package)."""
import json
import os
import re
import subprocess
import sys

import pytest


def run(*cmd, env=None):
    p = subprocess.run(list(cmd), capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0, f"{cmd} failed:\n{p.stdout}\n{p.stderr}"
    return p.stdout


def test_the_program_runs_every_analysis_on_the_users_model(opts):
    out = run(opts["example"], "--quick")
    label = re.search(r"d = 2: (\S+),", out).group(1)
    assert label.startswith("P")
    per, right, left = map(int, re.search(r"(\d+) impact\(s\) per period \(right (\d+), left (\d+)\)", out).groups())
    assert per == right + left and right > 0 and left > 0, out
    # The trivial multiplier is 1 (the flow direction is mapped onto itself), and the
    # determinant of the monodromy is the Liouville value exp(int div F) prod det S: two
    # independent computations of one number.
    trivial = float(re.search(r"\|mu - 1\| = ([0-9.e+-]+)", out).group(1))
    assert trivial < 1e-9, out
    det, liouville = map(float, re.search(r"det monodromy ([0-9.e+-]+), Liouville ([0-9.e+-]+)", out).groups())
    assert det == pytest.approx(liouville, rel=1e-6)
    # The sum of the Lyapunov exponents equals <div F> + the impact rate times ln|det S|.
    total, rule = map(float, re.search(r"sum ([-0-9.e+]+), sum rule ([-0-9.e+]+)", out).groups())
    assert total == pytest.approx(rule, abs=1e-8)
    assert len(re.findall(r" \d\S*:P\d+| \d\S*:aperiodic", out)) == 7


def test_the_plugin_is_a_model_of_the_command_line(opts):
    if not opts["vimpact"]:
        pytest.skip("the command-line program is not built")
    models = json.loads(run(opts["vimpact"], "models", opts["plugin"], "--json"))["models"][0]
    assert models["name"] == "impact_damper"
    assert [p["name"] for p in models["parameters"]] == ["zeta", "a", "w", "mu", "d", "r"]
    assert [s["name"] for s in models["surfaces"]] == ["right", "left"]
    j = json.loads(run(opts["vimpact"], "period", "--model", opts["plugin"], "--transient", "100", "--record", "40",
                       "--json"))
    program = run(opts["example"], "--quick")
    assert j["label"] == re.search(r"d = 2: (\S+),", program).group(1)
    assert sum(j["impacts_by_surface"].values()) == j["impacts"]


def test_a_plugin_run_replays_only_with_the_plugin_on_the_command_line(opts, tmp_path):
    # A config file never loads native code: the plugin's run.toml names it, and the replay
    # gives it again with --model.
    if not opts["vimpact"]:
        pytest.skip("the command-line program is not built")
    first, again = tmp_path / "first", tmp_path / "again"
    run(opts["vimpact"], "period", "--model", opts["plugin"], "--transient", "60", "--record", "20", "--no-plot",
        "--out", str(first))
    cfg = first / "config.toml"
    plugin = os.path.abspath(opts["plugin"])
    assert f"--model '{plugin}' --config config.toml" in cfg.read_text()
    p = subprocess.run([opts["vimpact"], "period", "--config", str(cfg), "--out", str(again)], capture_output=True,
                       text=True, timeout=600)
    assert p.returncode == 2 and "names a shared library" in p.stderr and not again.exists(), p.stderr
    run(opts["vimpact"], "period", "--model", plugin, "--config", str(cfg), "--out", str(again))
    for name in ("sections.csv", "config.toml"):
        assert (first / name).read_bytes() == (again / name).read_bytes(), name


def test_impacts_of_the_plugin_keep_momentum_and_reverse_the_relative_velocity(opts):
    python_dir = os.path.join(opts["build"], "python")
    if not os.path.isdir(os.path.join(python_dir, "vimpact")):
        pytest.skip("the Python module is not built")
    code = f"""
import sys, numpy as np, vimpact
m = vimpact.Model.from_file({opts["plugin"]!r})
s = vimpact.simulate(m, transient=50, record=20)
pre, post = s.impact_pre, s.impact_post
mu, r = m.mu, m.r
momentum = lambda x: x[:, 1] + mu * x[:, 3]
relative = lambda x: x[:, 3] - x[:, 1]
assert len(pre) > 5, len(pre)
print(np.max(np.abs(momentum(post) - momentum(pre))), np.max(np.abs(relative(post) + r * relative(pre))))
"""
    env = dict(os.environ, PYTHONPATH=python_dir)
    dp, du = map(float, run(sys.executable, "-c", code, env=env).split())
    assert dp < 1e-13 and du < 1e-13


@pytest.mark.skipif(os.environ.get("VIMPACT_SKIP_INSTALL_TEST") == "1", reason="VIMPACT_SKIP_INSTALL_TEST=1")
def test_the_example_builds_against_an_installed_vimpact(opts, tmp_path):
    prefix = tmp_path / "prefix"
    run("cmake", "--install", opts["build"], "--prefix", str(prefix))
    build = tmp_path / "example"
    run("cmake", "-S", os.path.join(opts["source"], "examples", "cpp"), "-B", str(build),
        "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}")
    run("cmake", "--build", str(build), "-j2")
    assert run(str(build / "run_impact_damper"), "--quick") == run(opts["example"], "--quick")
