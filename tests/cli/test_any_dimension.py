"""A model file of a dimension the library has no fixed-size instance for (12 states: four
decoupled copies of the two-sided impact oscillator, copy k with forcing amplitude a_k) runs
`vimpact period`; its label and impacts per period follow from the one-copy model's runs."""
import math

from test_cli import run_json


def copies_toml(K):
    lines = [f'name = "copies{K}"',
             "state = [" + ", ".join(f'"x{k}", "v{k}", "p{k}"' for k in range(K)) + "]",
             "[parameters]", "zeta = { default = 0.05 }", "w = { default = 1.2, above = 0 }",
             "d = { default = 1.0 }", "r = { default = 0.8 }"]
    lines += [f"a{k} = {{ default = 1.0 }}" for k in range(K)]
    lines.append("[derivatives]")
    for k in range(K):
        lines += [f'x{k} = "v{k}"', f'v{k} = "-2*zeta*v{k} - x{k} + a{k}*cos(p{k})"', f'p{k} = "w"']
    lines.append("[angles]")
    lines += [f'p{k} = "2*pi"' for k in range(K)]
    for k in range(K):
        lines += ["[[surfaces]]", f'name = "right{k}"', f'gap = "d - x{k}"', f'reset = {{ v{k} = "-r*v{k}" }}',
                  "[[surfaces]]", f'name = "left{k}"', f'gap = "x{k} + d"', f'reset = {{ v{k} = "-r*v{k}" }}']
    lines += ["[[sections]]", 'name = "strobe"', 'when = "sin(p0)"', 'direction = "up"']
    return "\n".join(lines) + "\n"


def test_a_twelve_state_model_file_runs_period(vimpact, tmp_path):
    K = 4
    many, one = tmp_path / "copies4.toml", tmp_path / "copies1.toml"
    many.write_text(copies_toml(K))
    one.write_text(copies_toml(1))
    amplitudes = [1.0 + 0.01 * k for k in range(K)]
    singles = [run_json(vimpact, "period", "--model", str(one), "--set", f"a0={a}") for a in amplitudes]
    for s in singles:
        assert s["period"] > 0, s["label"]
    period = math.lcm(*(s["period"] for s in singles))
    args = [x for k, a in enumerate(amplitudes) for x in ("--set", f"a{k}={a}")]
    j = run_json(vimpact, "period", "--model", str(many), *args, "--transient", str(500 * K))
    assert j["label"] == f"P{period}"
    assert j["impacts"] == sum(s["impacts"] * (period // s["period"]) for s in singles)
