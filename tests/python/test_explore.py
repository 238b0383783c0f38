"""vimpact explore: the page's requests give the library's results as the command line gives them,
the server refuses what the page may not ask, stops on Ctrl-C, and a click in a real (headless)
browser shows the label the command line prints for the clicked point."""
import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request

import numpy as np
import pytest

import vimpact
from vimpact import explore

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from capabilities import need  # noqa: E402

# A window of the paper's diagram with P2 and P3 orbits (the docstrings' sweep of Ur 15..20).
WINDOW = dict(name="Ur", lo=15.0, hi=20.0, n=24)


@pytest.fixture(scope="module")
def server():
    model = vimpact.Model("wake_impact")
    srv = explore.serve(explore.Explorer(model, "wake_impact"), 0)
    thread = threading.Thread(target=srv.serve_forever, daemon=True)
    thread.start()
    yield srv
    srv.shutdown()
    srv.server_close()


def request(srv, path, body=None, headers=None):
    url = f"http://127.0.0.1:{srv.server_address[1]}{path}"
    data = None if body is None else json.dumps(body).encode()
    try:
        with urllib.request.urlopen(urllib.request.Request(url, data=data, headers=headers or {}), timeout=120) as r:
            return r.status, json.load(r) if path.startswith("/api/") else r.read()
    except urllib.error.HTTPError as e:
        return e.code, json.load(e)


def run_cli(cli, command):
    """A command line the page shows, run with the built program, its --json summary."""
    words = shlex.split(command)
    assert words[0] == "vimpact"
    return json.loads(cli(*words[1:], "--json").stdout)


def test_the_server_listens_on_the_local_machine_only(server):
    assert server.server_address[0] == "127.0.0.1"


def test_a_diagrams_levels_together_are_the_whole_sweep(server):
    """Coarse first, then the values between: every value of the grid once, each with the
    points and label the whole sweep gives it (an independent call of vimpact.sweep)."""
    got = []
    for level in range(4):
        code, r = request(server, "/api/diagram", dict(parameters={}, axis=WINDOW, level=level))
        assert code == 200, r
        got.append(r)
    assert [len(r["values"]) for r in got] == [3, 3, 6, 12]  # stride 8 over 24 values, then halving
    whole = vimpact.sweep(vimpact.Model("wake_impact"), "Ur", vimpact.grid(WINDOW["lo"], WINDOW["hi"], WINDOW["n"]))
    values = np.concatenate([r["values"] for r in got])
    order = np.argsort(values)
    assert np.array_equal(values[order], whole.value)
    labels = np.concatenate([r["labels"] for r in got])
    assert labels[order].tolist() == whole.label.tolist()
    xs = np.concatenate([r["x"] for r in got])
    ys = np.concatenate([r["y"] for r in got])
    assert sorted(zip(xs, ys)) == sorted(zip(whole.point_value, whole.points[:, 0]))
    assert got[-1]["last"] and got[0]["command"].endswith("--param Ur --range 15.0:20.0:24")


def test_a_map_level_is_the_map_of_its_cells(server):
    x, y = dict(name="Ur", lo=15.0, hi=20.0, n=9), dict(name="sigma", lo=-0.2, hi=-0.1, n=5)
    code, r = request(server, "/api/map", dict(parameters={}, x=x, y=y, level=1))
    assert code == 200, r
    xs, ys = vimpact.grid(15.0, 20.0, 9)[::2], vimpact.grid(-0.2, -0.1, 5)[::2]
    assert np.array_equal(r["x"], xs) and np.array_equal(r["y"], ys)
    whole = vimpact.map(vimpact.Model("wake_impact"), ("Ur", xs), ("sigma", ys))
    assert r["label"] == whole.label.tolist()


def test_a_point_is_what_the_command_line_says(server, cli):
    code, r = request(server, "/api/point", dict(parameters={"Ur": 19.0, "A": 12.5}))
    assert code == 200, r
    assert r["command"] == "vimpact period --model wake_impact --set Ur=19.0 --set A=12.5"
    assert r["label"] == run_cli(cli, r["command"])["label"]
    fl = json.loads(cli("floquet", "--set", "Ur=19.0", "--set", "A=12.5", "--json").stdout)
    assert r["label"] == fl["label"]
    assert np.allclose(r["multipliers"], fl["multipliers"], rtol=0, atol=1e-12)
    # The window shown is the recorded one: its impacts are on the barrier (y = sigma).
    sigma = vimpact.Model("wake_impact").sigma
    assert len(r["impact_t"]) > 0 and np.allclose(r["impact_state"][0], sigma, atol=1e-9)


def test_a_basins_click_starts_from_the_clicked_state(server, cli):
    code, r = request(server, "/api/point", dict(parameters={"Ur": 16.0}, state={"y": 0.05, "ydot": -0.1}))
    assert code == 200, r
    assert "--ic" in r["command"]
    assert r["label"] == run_cli(cli, r["command"])["label"]


@pytest.mark.parametrize("path, body, words", [
    ("/api/point", dict(parameters={"nope": 1.0}), "parameter 'nope' is not one of the model's"),
    ("/api/point", dict(parameters={"Ur": "1e400"}), "parameter Ur must be a finite number"),
    ("/api/point", dict(parameters={"Ur": -1.0}), "outside its valid range"),
    ("/api/point", dict(parameters={}, state={"q": 0.0}), "state 'q' is not a state variable"),
    ("/api/diagram", dict(parameters={}, axis=dict(WINDOW, n=10**6), level=0), "axis.n must be an integer in [2, 2000]"),
    ("/api/diagram", dict(parameters={}, axis=dict(WINDOW, name="y"), level=0), "axis 'y' is not a parameter"),
    ("/api/diagram", dict(parameters={}, axis=WINDOW, level=9), "level must be an integer in [0, 3]"),
    ("/api/map", dict(parameters={}, x=dict(WINDOW, n=500), y=WINDOW, level=0), "x.n must be an integer in [2, 160]"),
])
def test_a_request_out_of_range_is_refused_by_name(server, path, body, words):
    code, r = request(server, path, body)
    assert code == 400 and words in r["error"], r


@pytest.mark.parametrize("path", ["/../etc/passwd", "/explore.py", "/api/../explore.html", "/etc/passwd"])
def test_the_page_reads_no_file(server, path):
    code, r = request(server, path)
    assert code == 404


def test_requests_of_another_site_or_host_name_are_refused(server):
    port = server.server_address[1]
    # DNS rebinding: a name that resolves to this machine, but not the server's own address.
    assert request(server, "/api/model", headers={"Host": f"attacker.example:{port}"})[0] == 403
    # A page of another site posting to the server (the browser names the page's origin).
    body = dict(parameters={"Ur": 19.0})
    assert request(server, "/api/point", body, headers={"Origin": "http://attacker.example"})[0] == 403
    assert request(server, "/api/point", body, headers={"Origin": f"http://127.0.0.1:{port + 1}"})[0] == 403
    # The page itself, by either name of this machine.
    for host in (f"127.0.0.1:{port}", f"localhost:{port}"):
        code, r = request(server, "/api/point", body, headers={"Host": host, "Origin": f"http://{host}"})
        assert code == 200 and r["label"] == "P3"


def test_a_newer_view_stops_an_older_one(server):
    _, a = request(server, "/api/view", {})
    _, b = request(server, "/api/view", {})
    assert b["view"] > a["view"]
    code, r = request(server, "/api/diagram", dict(parameters={}, axis=WINDOW, level=0, view=a["view"]))
    assert code == 409
    code, r = request(server, "/api/diagram", dict(parameters={}, axis=WINDOW, level=0, view=b["view"]))
    assert code == 200


def start_cli_server(vimpact_cli, *args):
    p = subprocess.Popen([vimpact_cli, "explore", "--no-browser", "--port", "0", *args], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    line = p.stdout.readline()
    m = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    assert m, (line, p.stderr.read() if p.poll() is not None else "")
    return p, m.group(0)


def test_the_command_serves_the_model_and_ctrl_c_stops_it(vimpact_cli):
    p, url = start_cli_server(vimpact_cli, "--set", "Ur=18")
    try:
        with urllib.request.urlopen(url + "api/model", timeout=30) as r:
            info = json.load(r)
        assert info["name"] == "wake_impact"
        assert {q["name"]: q["value"] for q in info["parameters"]}["Ur"] == 18.0
        with urllib.request.urlopen(url, timeout=30) as r:
            assert b"plotly.js" in r.read()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=20)
    finally:
        p.kill()
    assert p.returncode == 0 and "stopped" in out, (out, err)


@pytest.mark.parametrize("args, words", [(["--set", "Ur=-1"], "Ur = -1 is outside its valid range"),
                                         (["--model", "no_such_model.toml"], "does not exist"),
                                         (["--preset", "nope"], "preset")])
def test_the_command_refuses_bad_input_with_exit_code_2(vimpact_cli, args, words):
    r = subprocess.run([vimpact_cli, "explore", "--no-browser", "--port", "0", *args], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 2 and words in r.stderr, r.stderr


def browser():
    """Headless Chromium through selenium, or why not."""
    try:
        from selenium import webdriver
    except ImportError:
        return None, "python3-selenium is not installed"
    driver = shutil.which("chromedriver") or "/usr/bin/chromedriver"
    if not os.path.exists(driver):
        return None, "chromium-driver is not installed"
    from selenium.webdriver.chrome.service import Service
    o = webdriver.ChromeOptions()
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1400,900"):
        o.add_argument(arg)
    return webdriver.Chrome(service=Service(driver), options=o), ""


def test_a_click_in_a_browser_shows_the_command_lines_label(vimpact_cli, cli, tmp_path):
    b, why = browser()
    need("browser", b is not None, why)
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait
    p, url = start_cli_server(vimpact_cli, "--threads", "2")
    try:
        b.get(url)
        wait = WebDriverWait(b, 120, poll_frequency=0.2)
        wait.until(lambda d: d.execute_script("return window.explorer && !!window.explorer.info && "
                                              "document.getElementById('axis-lo') !== null"))
        for key, value in (("axis-lo", "15"), ("axis-hi", "20"), ("axis-n", "24")):
            e = b.find_element(By.ID, key)
            e.clear()
            e.send_keys(value)
        b.find_element(By.ID, "compute").click()
        wait.until(lambda d: d.execute_script("const e = window.explorer; return !e.busy && e.data && "
                                              "e.data.values.length === 24"))
        # A point of the diagram near Ur = 19 (a P3 window), where the page draws it.
        x, y, dx, dy = b.execute_script("""
            const e = window.explorer, gd = document.getElementById('view');
            let k = 0;
            e.data.x.forEach((v, i) => { if (Math.abs(v - 19) < Math.abs(e.data.x[k] - 19)) k = i; });
            const xa = gd._fullLayout.xaxis, ya = gd._fullLayout.yaxis, r = gd.getBoundingClientRect();
            return [e.data.x[k], e.data.y[k], xa._offset + xa.l2p(e.data.x[k]) - r.width / 2,
                    ya._offset + ya.l2p(e.data.y[k]) - r.height / 2];""")
        ActionChains(b).move_to_element_with_offset(b.find_element(By.ID, "view"), int(dx), int(dy)).pause(0.3) \
            .click().perform()
        wait.until(lambda d: d.find_element(By.ID, "point-label").text not in ("", "..."))
        shown = b.find_element(By.ID, "point-label").text
        where = b.find_element(By.ID, "point-where").text
        command = b.find_element(By.ID, "point-command").text
        artefacts = os.environ.get("VIMPACT_TEST_ARTIFACTS") or str(tmp_path)
        os.makedirs(artefacts, exist_ok=True)
        b.save_screenshot(os.path.join(artefacts, "explore.png"))
    finally:
        b.quit()
        p.send_signal(signal.SIGINT)
        p.communicate(timeout=30)
    clicked = float(where.split("=")[1])
    assert abs(clicked - x) < 0.05, (where, x, y)  # the click hit a point of the value aimed at
    assert shown == json.loads(cli("period", "--set", f"Ur={clicked!r}", "--json").stdout)["label"]
    assert shown == run_cli(cli, command)["label"]
