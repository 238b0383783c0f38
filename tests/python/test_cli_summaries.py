"""The command line's summary of a single run (--json, run.json's result) against the module's
record of the same run: two visitors of one description (cli/output.hpp record_json,
python/bindings/records.hpp record_dict) must give every field with the same value, bit for
bit, under the field's name or the summary's name for it. Skipped where the program is not
built."""
import numpy as np
import pytest

import vimpact

# A short protocol keeps the comparison to a few seconds.
Q = dict(transient=80, record=40)
QA = ["--transient", "80", "--record", "40"]

# The summaries' keys that are not the field's name (cli/stability_commands.cpp).
RENAMED = {
    "floquet": {"status": "outcome", "protocol_stats": "stats/protocol", "tangent_stats": "stats/tangent"},
    "lyapunov": {"status": "outcome", "transient_stats": "stats/transient", "stats": "stats/tangent"},
    "period": {},
}


def real(v):
    """JSON null (not finite) as NaN."""
    return np.array(np.nan if v is None else v, dtype=float)


def same_field(f, mine, summary):
    kind, span = f["type"], f["span"]
    if kind == "group":
        assert set(summary) == {g["name"] for g in f["fields"]}
        for g in f["fields"]:
            same_field(g, mine[g["name"]], summary[g["name"]])
    elif span == "per_surface":
        assert set(summary) == set(mine)
        for s in mine:
            np.testing.assert_array_equal(real(summary[s]), real(mine[s]))
    elif span == "spectrum":
        np.testing.assert_array_equal(np.array([complex(re, im) for re, im in summary]), np.asarray(mine))
    elif span == "per_state":
        np.testing.assert_array_equal(np.array([real(x) for x in summary]), np.asarray(mine, dtype=float))
    elif kind == "float":
        np.testing.assert_array_equal(real(summary), np.asarray(mine, dtype=float))
    else:
        assert summary == mine, f["name"]


@pytest.mark.parametrize("record,args,run", [
    ("floquet", ["floquet", "--set", "Ur=16"], lambda: vimpact.floquet(vimpact.WakeImpact(Ur=16))),
    ("lyapunov", ["lyapunov", "--set", "Ur=16", "--impacts", "60", "--transient", "100"],
     lambda: vimpact.lyapunov(vimpact.WakeImpact(Ur=16), impacts=60, transient=100)),
    ("period", ["period", *QA], lambda: vimpact.period(vimpact.WakeImpact(), **Q))])
def test_a_single_runs_summary_is_its_described_record(cli_json, record, args, run):
    summary, result = cli_json(*args), run()
    for f in vimpact._vimpact.described[record]:
        key = RENAMED[record].get(f["name"], f["name"])
        if f["span"] == "series":  # a table of its own, never in the summary
            assert key not in summary
            continue
        value = summary
        for part in key.split("/"):
            value = value[part]
        # The module keeps the counters in `stats`, by the summary's names.
        mine = result.record[f["name"]] if f["name"] in result.record else result.stats[key.split("/")[-1]]
        same_field(f, getattr(mine, "record", mine), value)


@pytest.mark.parametrize("kind,args,run", [
    ("Floquet", ["floquet", "--set", "Ur=19", *QA], lambda: vimpact.floquet(vimpact.WakeImpact(Ur=19), **Q)),
    ("Lyapunov", ["lyapunov", "--set", "Ur=19", "--impacts", "60", "--transient", "100"],
     lambda: vimpact.lyapunov(vimpact.WakeImpact(Ur=19), impacts=60, transient=100))])
def test_a_loaded_single_run_has_the_computed_records_values(cli, tmp_path, kind, args, run):
    # What run.json holds of the record comes back by the same name, bit for bit: none of its
    # fields is replaced by NaN on loading.
    assert cli(*args, "--out", str(tmp_path / "run"), "--no-plot").returncode == 0
    loaded, computed = getattr(vimpact, kind).load(str(tmp_path / "run")), run()
    record = kind.lower()
    for f in vimpact._vimpact.described[record]:
        if f["span"] == "series" or f["type"] == "group" or f["name"] not in computed.record:
            continue
        assert f["name"] in loaded.record, f["name"]
        if f["type"] == "float" and f["span"] == "one":
            np.testing.assert_array_equal(real(loaded.record[f["name"]]), real(computed.record[f["name"]]),
                                          err_msg=f["name"])
