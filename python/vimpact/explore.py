"""vimpact explore: a bifurcation diagram, periodicity map or basins of one model in the browser.

``python3 -m vimpact.explore --model wake_impact`` (or ``vimpact explore``) serves a page on
127.0.0.1 that computes the chosen view progressively (a coarse picture first, then finer), lets
every parameter of the model be changed, recomputes the window a zoom selects, and shows, for a
clicked point, its orbit in phase space, time series, impacts, period label and Floquet
multipliers. Every view and point gives the command line that reproduces it.

What the page can do is bounded by what the server was started with: it names no file and no
model, only parameter values of the one model loaded at start, view axes among that model's
parameters and state variables, and grid sizes within the limits below. The computations are the
library's own (``vimpact.sweep``, ``map``, ``basins``, ``period``, ``floquet``, ``simulate``), with
their defaults, so a label shown is the label the command line prints for the same point.
"""
import argparse
import json
import math
import os
import shlex
import sys
import threading
import webbrowser
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import numpy as np

# Grid sizes a page may ask for: enough for a sharp picture, small enough that one request
# cannot occupy the machine for minutes.
MAX_VALUES = 2000
MAX_CELLS = 160
# The diagram's values computed first: every STRIDE-th, then the ones between, halving.
STRIDE = 8
# Where Debian's python3-plotly puts plotly.js, then where a pip install of plotly does.
_PLOTLY_PATHS = ("/usr/share/python3-plotly/plotly.js", "/usr/share/javascript/plotly/plotly.min.js")
_PAGE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "explore.html")


class RequestError(ValueError):
    """A request the page should not have sent: the message says which input and its range."""


class _Superseded(Exception):
    """A newer view started: the computation of an older one stops."""


def plotly_path():
    """plotly.js from the machine (no network), or None."""
    for p in _PLOTLY_PATHS:
        if os.path.isfile(p):
            return p
    try:
        import plotly
        p = os.path.join(os.path.dirname(plotly.__file__), "package_data", "plotly.min.js")
        return p if os.path.isfile(p) else None
    except ImportError:
        return None


def _number(value, what):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise RequestError(f"{what} must be a finite number (got {value!r})")
    return float(value)


def _count(value, what, lo, hi):
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise RequestError(f"{what} must be an integer in [{lo}, {hi}] (got {value!r})")
    return value


def _range_text(lo, hi, n):
    return f"{lo!r}:{hi!r}:{n}"


class Explorer:
    """The computations behind the page, for one model. ``spec`` is how the command line names
    the model (a built-in name or a file); ``base`` the model as loaded from it, without any
    parameter set, against which a view's command lists the parameters that differ."""

    def __init__(self, model, spec, base=None, threads=0):
        import vimpact
        self._v = vimpact
        self.model = model
        self.spec = spec
        self.base = base if base is not None else model
        self.threads = threads
        self._lock = threading.Lock()
        self._view = 0
        self._view_lock = threading.Lock()

    # ---------------------------------------------------------------- inputs

    def info(self):
        i = self.model.info
        return dict(name=self.model.name, description=i["description"],
                    parameters=[dict(name=p["name"], meaning=p["meaning"], unit=p.get("unit", ""),
                                     value=v) for p, v in zip(i["parameters"], self.model.parameters.values())],
                    state=[dict(name=s["name"], meaning=s["meaning"]) for s in i["state"]])

    def _model_at(self, parameters):
        if not isinstance(parameters, dict):
            raise RequestError("parameters must be an object {name: value}")
        names = self.model.parameter_names
        for k in parameters:
            if k not in names:
                raise RequestError(f"parameter '{k}' is not one of the model's: {', '.join(names)}")
        return self.model.with_(**{k: _number(v, f"parameter {k}") for k, v in parameters.items()})

    def _parameter(self, name, what):
        if name not in self.model.parameter_names:
            raise RequestError(f"{what} '{name}' is not a parameter of the model: "
                               f"{', '.join(self.model.parameter_names)}")
        return name

    def _state(self, name, what):
        if name not in self.model.state_names:
            raise RequestError(f"{what} '{name}' is not a state variable of the model: "
                               f"{', '.join(self.model.state_names)}")
        return self.model.state_names.index(name)

    def _axis(self, req, key, names, most):
        a = req.get(key)
        if not isinstance(a, dict):
            raise RequestError(f"{key} must be an object {{name, lo, hi, n}}")
        name = names(a.get("name"), key)
        lo, hi = _number(a.get("lo"), f"{key}.lo"), _number(a.get("hi"), f"{key}.hi")
        n = _count(a.get("n"), f"{key}.n", 2, most)
        return name, lo, hi, n

    def command(self, words, model):
        """The command line of `words` (the command and its own options) on `model`."""
        line = ["vimpact", words[0], "--model", self.spec]
        for k, v in model.parameters.items():
            if v != self.base.parameters[k]:
                line += ["--set", f"{k}={v!r}"]
        return shlex.join(line + list(words[1:]))

    # ---------------------------------------------------------------- progressive views

    def start_view(self):
        """A new view: the computations of older ones stop at their next progress report."""
        with self._view_lock:
            self._view += 1
            return self._view

    def _progress(self, view):
        def report(done, total):
            if view != self._view:
                raise _Superseded()
        return report

    def diagram(self, req):
        """One level of a bifurcation diagram: level 0 the values j = 0, STRIDE, 2 STRIDE, ... of
        the grid lo:hi:n, each further level the values halfway between those computed before
        (the last, the odd j). Each value runs from the same initial state, so a level's points
        are those of the whole sweep (the command line's)."""
        m = self._model_at(req.get("parameters", {}))
        param, lo, hi, n = self._axis(req, "axis", self._parameter, MAX_VALUES)
        level = _count(req.get("level"), "level", 0, 3)
        var = self._state(req.get("variable", self.model.state_names[0]), "variable")
        j = np.arange(n)
        step = STRIDE >> level
        mine = j % step == 0 if level == 0 else (j % step == 0) & (j % (2 * step) != 0)
        values = self._v.grid(lo, hi, n)[mine]
        out = dict(level=level, last=step == 1,
                   command=self.command(["sweep", "--param", param, "--range", _range_text(lo, hi, n)], m))
        if values.size == 0:
            return dict(out, x=[], y=[], label=[], values=[], labels=[])
        s = self._run(req, lambda p: self._v.sweep(m, param, values, threads=self.threads, progress=p))
        return dict(out, x=s.point_value.tolist(), y=s.points[:, var].tolist(),
                    label=[str(s.label[r]) for r in s.point_run], values=s.value.tolist(),
                    labels=[str(x) for x in s.label])

    def grid(self, req, kind):
        """One level of a periodicity map (kind "map": two parameters) or of basins (kind
        "basins": two state variables, the others from the model's initial state): level 0
        every fourth cell of each axis, level 1 every second, level 2 all."""
        m = self._model_at(req.get("parameters", {}))
        if kind == "map":
            names = self._parameter
        else:
            def names(name, what):
                return self.model.state_names[self._state(name, what)]
        (xn, x0, x1, nx), (yn, y0, y1, ny) = (self._axis(req, k, names, MAX_CELLS) for k in ("x", "y"))
        level = _count(req.get("level"), "level", 0, 2)
        stride = 4 >> level
        xs, ys = self._v.grid(x0, x1, nx)[::stride], self._v.grid(y0, y1, ny)[::stride]
        call = self._v.map if kind == "map" else self._v.basins
        r = self._run(req, lambda p: call(m, (xn, xs), (yn, ys), threads=self.threads, progress=p))
        out = dict(level=level, last=stride == 1, x=xs.tolist(), y=ys.tolist(), label=r.label.tolist(),
                   command=self.command([kind, "--x", f"{xn}:{_range_text(x0, x1, nx)}",
                                         "--y", f"{yn}:{_range_text(y0, y1, ny)}"], m))
        if kind == "basins":
            out["attractor"] = r.attractor.tolist()
            out["attractors"] = [dict(id=a.id, label=a.label, cells=int(a.cells)) for a in r.attractors]
        return out

    def _run(self, req, call):
        view = req.get("view")
        with self._lock:
            if view is not None and view != self._view:
                raise _Superseded()
            return call(self._progress(view) if view is not None else None)

    # ---------------------------------------------------------------- a point

    def point(self, req):
        """A clicked point: the model at the view's parameters (and the clicked ones), from the
        model's initial state, or from a clicked initial state (basins). Its period label and
        Floquet multipliers (one protocol run: Floquet's label is the protocol's, as `period`
        gives it; `period` alone where the model has no crossing section), and the recorded
        window of its run: orbit, time series, impacts."""
        m = self._model_at(req.get("parameters", {}))
        ic = np.array(self.model.default_ic)
        words = ["period"]
        start = req.get("state", {})
        if not isinstance(start, dict):
            raise RequestError("state must be an object {state variable: value}")
        for k, v in start.items():
            ic[self._state(k, "state")] = _number(v, f"state {k}")
        if start:
            words += ["--ic", ",".join(repr(float(v)) for v in ic)]
        with self._lock:
            s = self._v.simulate(m, ic, sample_dt=0.02)
            try:
                f = self._v.floquet(m, ic)
                label, why = f.label, None
            except self._v.InputError as e:  # floquet needs a section crossing
                f, why = None, str(e)
                label = self._v.period(m, ic).label
        have = f is not None and f.status in ("ok", "not_converged")
        mult = [[float(z.real), float(z.imag)] for z in f.multipliers] if have else []
        keep = s.series_t <= s.series_t[0] + 200.0 if len(s.series_t) else slice(None)
        return dict(label=label, outcome=str(s.outcome), period=_finite(f.period) if have else None,
                    floquet_status=str(f.status) if f is not None else why, multipliers=mult,
                    stable=bool(f.stable) if f is not None else False, state_names=list(self.model.state_names),
                    t=s.series_t[keep].tolist(), series=s.series[keep].T.tolist(),
                    impact_t=s.impact_t.tolist(), impact_state=s.impact_pre.T.tolist(),
                    section=s.section.T.tolist(), command=self.command(words, m))


def _finite(x):
    x = float(x)
    return x if math.isfinite(x) else None


class _Handler(BaseHTTPRequestHandler):
    explorer = None  # set on the server's own subclass
    plotly = None

    def log_message(self, *args):  # quiet: the terminal shows the address and errors only
        pass

    def _send(self, code, body, kind):
        self.send_response(code)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(body)

    def _json(self, code, obj):
        self._send(code, json.dumps(obj, allow_nan=False).encode(), "application/json")

    def _foreign(self):
        """Whether another site's page made the browser send this request: a Host other than
        this server's address (DNS rebinding) or an Origin other than the page's own (a
        cross-site POST). Only the page this server serves may use it."""
        port = self.server.server_address[1]
        ours = {f"127.0.0.1:{port}", f"localhost:{port}"}
        origin = self.headers.get("Origin")
        return self.headers.get("Host") not in ours or (origin is not None and origin not in
                                                         {f"http://{h}" for h in ours})

    def _refused(self):
        if self._foreign():
            self._json(403, dict(error="requests from another site or host name are refused"))
            return True
        return False

    def do_GET(self):
        if self._refused():
            return
        if self.path == "/":
            with open(_PAGE, "rb") as f:
                self._send(200, f.read(), "text/html; charset=utf-8")
        elif self.path == "/plotly.js" and self.plotly:
            with open(self.plotly, "rb") as f:
                self._send(200, f.read(), "application/javascript")
        elif self.path == "/api/model":
            self._json(200, self.explorer.info())
        else:
            self._json(404, dict(error=f"no such page: {self.path[:80]}"))

    def do_POST(self):
        if self._refused():
            return
        ex = self.explorer
        routes = {"/api/view": lambda r: dict(view=ex.start_view()), "/api/diagram": ex.diagram,
                  "/api/map": lambda r: ex.grid(r, "map"), "/api/basins": lambda r: ex.grid(r, "basins"),
                  "/api/point": ex.point}
        route = routes.get(self.path)
        if route is None:
            return self._json(404, dict(error=f"no such request: {self.path[:80]}"))
        try:
            n = int(self.headers.get("Content-Length", "0"))
            if not 0 <= n <= 1 << 16:
                raise RequestError("request too large")
            req = json.loads(self.rfile.read(n) or b"{}")
            if not isinstance(req, dict):
                raise RequestError("a request is a JSON object")
            self._json(200, route(req))
        except _Superseded:
            self._json(409, dict(error="superseded by a newer view"))
        except (RequestError, json.JSONDecodeError, ex._v.InputError) as e:
            self._json(400, dict(error=str(e)))


def serve(explorer, port=0, host="127.0.0.1"):
    """A server of `explorer` bound to `host` (only the local machine by default); port 0
    picks a free one (server.server_address says which)."""
    handler = type("Handler", (_Handler,), dict(explorer=explorer, plotly=plotly_path()))
    server = ThreadingHTTPServer((host, port), handler)
    server.daemon_threads = True
    return server


def _parse_sets(items):
    out = {}
    for item in items:
        name, eq, value = item.partition("=")
        if not eq or not name:
            raise ValueError(f"--set {item!r} must be KEY=VALUE")
        try:
            out[name] = float(value)
        except ValueError:
            raise ValueError(f"--set {name}: '{value}' is not a number") from None
    return out


def main(argv=None):
    try:
        return _main(argv)
    except KeyboardInterrupt:  # Ctrl-C before the server listens (a model file compiling)
        print("vimpact explore: interrupted", file=sys.stderr)
        return 130


def _main(argv):
    ap = argparse.ArgumentParser(prog="vimpact explore", description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", default="wake_impact", help="a built-in name, a model file or a plugin")
    ap.add_argument("--preset", help="a parameter preset of the model")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="set a parameter (repeatable)")
    ap.add_argument("--port", type=int, default=8765, help="port on 127.0.0.1 (0: any free one; default 8765)")
    ap.add_argument("--threads", type=int, default=0, help="worker threads (0: every core)")
    ap.add_argument("--no-browser", action="store_true", help="do not open a browser, print the address only")
    a = ap.parse_args(argv)
    import vimpact
    if vimpact._import_error is not None:
        print(f"vimpact explore: the compiled module vimpact._vimpact is needed ({vimpact._import_error})",
              file=sys.stderr)
        return 2
    try:
        if not 0 <= a.port <= 65535:
            raise ValueError(f"--port must be in [0, 65535] (got {a.port})")
        if a.threads < 0:
            raise ValueError(f"--threads must be >= 0 (got {a.threads})")
        base = vimpact.Model(a.model)
        model = base.preset(a.preset) if a.preset else base
        model = model.with_(**_parse_sets(a.set))
    except (ValueError, vimpact.InputError) as e:
        print(f"vimpact explore: {e}", file=sys.stderr)
        return 2
    if plotly_path() is None:
        print("vimpact explore: plotly.js not found (install python3-plotly)", file=sys.stderr)
        return 2
    try:
        server = serve(Explorer(model, a.model, base, a.threads), a.port)
    except OSError as e:
        print(f"vimpact explore: cannot listen on 127.0.0.1:{a.port} ({e.strerror}; --port 0 picks a free one)",
              file=sys.stderr)
        return 2
    url = f"http://127.0.0.1:{server.server_address[1]}/"
    print(f"vimpact explore: {model.name} at {url} (Ctrl-C stops)", flush=True)
    if not a.no_browser:
        webbrowser.open(url)
    try:
        server.serve_forever(poll_interval=0.2)
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()
    print("vimpact explore: stopped", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
