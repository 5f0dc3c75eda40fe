"""`tidyplan serve`: an HTTP planner service in the shape of the VS Code PDDL extension's
synchronous planner service (docs/editor.md).

``POST /solve`` with ``{"domain": TEXT, "problem": TEXT}``; options in the query string
(``planner``, ``timeout``: seconds for a first plan, ``budget``: seconds to improve it,
``max-stratum``, ``strata=no``). The reply is ``{"status": "ok", "result": {"output", "plan":
[{"name": "(action arg ...)", ...}], ...}}``, or ``{"status": "error", "result": {"output",
"error"}}``: the extension shows ``output`` and ``error`` and keeps going. A reply is always
HTTP 200 (the extension treats any code above 202 as a failure of the service itself, not of
the planning), except 404 for another path and 405 for another method.

Each request plans in a process of its own (``tidyplan plan --json`` on the texts, in a fresh
folder), in a session of its own: a bad file or a crash of the planner never reaches the
server, and a request past its limit is ended whole (SIGTERM, whose clean-up stops the search;
SIGKILL to the session if that does not do it). The server makes itself the subreaper of its
descendants, so a search orphaned by a killed child comes back to it and is killed and reaped:
nothing outlives its request.

The standard library's ``ThreadingHTTPServer`` serves: one thread a request, no dependency, and
all the service needs (one endpoint, JSON both ways, loopback by default). The work is in the
child processes, so the threads only wait.
"""

from __future__ import annotations

import contextlib
import ctypes
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import parse_qs, urlparse

DEFAULT_LIMIT = 60.0  # the extension waits 60 s (x 1.1) for a reply
DEFAULT_BUDGET = 1.0
GRACE = 5.0  # beyond the limit: the child's own clean-up, then SIGKILL
_MAX_BODY = 64 * 1024 * 1024
_PR_SET_CHILD_SUBREAPER = 36


class BadRequest(Exception):
    pass


def options(query: str, limit: float) -> list[str]:
    """`tidyplan plan` options from the request's query string; `BadRequest` on a bad one."""
    q = {k: v[-1] for k, v in parse_qs(query, keep_blank_values=True).items()}
    known = {"planner", "timeout", "budget", "max-stratum", "strata"}
    unknown = sorted(set(q) - known)
    if unknown:
        raise BadRequest(f"unknown option {', '.join(unknown)} (options: {', '.join(sorted(known))})")
    out: list[str] = []
    if "planner" in q:
        out += ["--planner", q["planner"]]
    timeout = min(_number(q, "timeout", limit), limit)
    out += ["--first-plan-limit", f"{timeout:g}"]
    out += ["--time-budget", f"{min(_number(q, 'budget', DEFAULT_BUDGET), limit):g}"]
    if "max-stratum" in q:
        if not q["max-stratum"].isdigit() or int(q["max-stratum"]) < 1:
            raise BadRequest(f"max-stratum: a whole number of at least 1, not {q['max-stratum']!r}")
        out += ["--max-stratum", q["max-stratum"]]
    if q.get("strata", "yes").lower() in ("no", "false", "0"):
        out.append("--no-strata")
    return out


def _number(q: dict, key: str, default: float) -> float:
    if key not in q:
        return default
    try:
        value = float(q[key])
    except ValueError:
        raise BadRequest(f"{key}: not a number: {q[key]!r}") from None
    if not value > 0:
        raise BadRequest(f"{key}: must be positive, not {q[key]!r}")
    return value


class Service:
    """Runs the requests' planners; knows which children are its own (`active`) so that any
    other child (an orphan handed back to the subreaper) is ended and reaped."""

    def __init__(self, limit: float) -> None:
        self.limit = limit
        self.lock = threading.Condition()
        self.active: set[int] = set()

    def solve(self, body: dict, query: str) -> dict:
        domain, problem = body.get("domain"), body.get("problem")
        if not isinstance(domain, str) or not isinstance(problem, str):
            raise BadRequest('the body must be {"domain": text, "problem": text}')
        args = options(query, self.limit)
        with tempfile.TemporaryDirectory(prefix="tidyplan-serve-") as tmp:
            Path(tmp, "domain.pddl").write_text(domain, encoding="utf-8")
            Path(tmp, "problem.pddl").write_text(problem, encoding="utf-8")
            limit = float(args[args.index("--first-plan-limit") + 1])
            budget = float(args[args.index("--time-budget") + 1])
            cmd = [sys.executable, "-m", "tidyplan", "plan", "domain.pddl", "problem.pddl", "--json", *args]
            code, out, err, killed = self.run(cmd, tmp, limit + budget + GRACE)
        return reply(code, out, err, killed, limit)

    def run(self, cmd: list[str], cwd: str, timeout: float) -> tuple[int, str, str, bool]:
        env = {**os.environ, "PYTHONUNBUFFERED": "1"}
        with self.lock:  # held from the fork: `reap_orphans` never takes it for an orphan
            proc = subprocess.Popen(
                cmd,
                cwd=cwd,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                stdin=subprocess.DEVNULL,
                text=True,
                start_new_session=True,
                env=env,
            )
            self.active.add(proc.pid)
        killed = False
        try:
            try:
                out, err = proc.communicate(timeout=timeout)
            except subprocess.TimeoutExpired:
                killed = True
                _signal_group(proc.pid, signal.SIGTERM)
                try:
                    out, err = proc.communicate(timeout=GRACE)
                except subprocess.TimeoutExpired:
                    _signal_group(proc.pid, signal.SIGKILL)
                    out, err = proc.communicate()
        finally:
            if proc.poll() is None:  # the server itself is stopping
                _signal_group(proc.pid, signal.SIGKILL)
                proc.wait()
            _signal_group(proc.pid, signal.SIGKILL)  # anything left in its session
            with self.lock:
                self.active.discard(proc.pid)
                self.lock.notify_all()
            self.reap_orphans()
        return proc.returncode, out or "", err or "", killed

    def reap_orphans(self) -> None:
        """End and reap the children that are no request's: searches whose parent died."""
        with self.lock:
            for pid in _children() - self.active:
                with contextlib.suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)
                with contextlib.suppress(ChildProcessError):
                    os.waitpid(pid, 0)

    def stop(self) -> None:
        """Stop every request's planner (SIGTERM, then SIGKILL) and wait for their threads to
        reap them."""
        with self.lock:
            for pid in self.active:
                _signal_group(pid, signal.SIGTERM)
            if not self.lock.wait_for(lambda: not self.active, timeout=GRACE):
                for pid in self.active:
                    _signal_group(pid, signal.SIGKILL)
                self.lock.wait_for(lambda: not self.active, timeout=GRACE)


def _signal_group(pid: int, sig: int) -> None:
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(pid, sig)


def _children() -> set[int]:
    out: set[int] = set()
    with contextlib.suppress(OSError):
        for task in os.listdir("/proc/self/task"):
            with contextlib.suppress(OSError), open(f"/proc/self/task/{task}/children") as f:
                out |= {int(x) for x in f.read().split()}
    return out


def reply(code: int, out: str, err: str, killed: bool, limit: float) -> dict:
    """The extension's reply from `tidyplan plan --json`'s exit status and output."""
    messages = [line for line in err.splitlines() if line.strip()]
    if killed:
        text = f"the planner did not end within its limit ({limit:g} s) and was stopped"
        return {"status": "error", "result": {"output": err, "error": text, "timeout": True}}
    try:
        found = json.loads(out.strip().splitlines()[-1]) if out.strip() else None
    except json.JSONDecodeError:
        found = None
    if found is None:  # bad input (exit 2) or a fault: the messages say where
        text = "\n".join(messages) or f"the planner ended with status {code} and no answer"
        return {"status": "error", "result": {"output": err, "error": text, "diagnostics": messages}}
    status = found["status"]
    plan = [
        {
            "name": "(" + " ".join([s["name"], *s["args"]]) + ")",
            "assumption": s["assumption"],
            "stratum": s["stratum"],
            "probability": s["probability"],
            "cost": s["cost"],
        }
        for s in found["plan"]
    ]
    output = _output(found, plan, messages)
    if status == "solved":
        result = {"output": output, "plan": plan, "length": len(plan), "type": "full"}
        for key in ("cost", "probability", "criterion", "reward", "stratum", "strata", "planning_time_s"):
            result[key] = found.get(key)
        result["planner"] = found.get("engine")
        return {"status": "ok", "result": result}
    if status == "not-found-in-time":
        text = f"no plan found within the first-plan limit ({limit:g} s)"
        return {"status": "error", "result": {"output": output, "error": text, "timeout": True}}
    if status in ("no-plan", "unknown"):
        return {"status": "ok", "result": {"output": output, "plan": [], "length": 0, "type": "full"}}
    return {"status": "error", "result": {"output": output, "error": "\n".join(messages) or status}}


def _output(found: dict, plan: list[dict], messages: list[str]) -> str:
    lines = [
        f"{i:3d} {'assume' if s['assumption'] else '      '} P{s['stratum']} {s['name']}  "
        f"cost {s['cost']:g}  p {s['probability']:g}"
        for i, s in enumerate(plan, 1)
    ]
    if found.get("criterion") is not None:
        lines.append(
            f"cost {found['cost']:g}, success probability {found['probability']:.4g}, "
            f"criterion c + R(1 - p) = {found['criterion']:.4g} (R = {found['reward']:g}), "
            f"stratum P{found['stratum']}"
        )
    lines.append(f"status {found['status']}; planning time {found.get('planning_time_s', 0):.2f}s")
    return "\n".join(lines + messages) + "\n"


class _Handler(BaseHTTPRequestHandler):
    service: Service
    server_version = "tidyplan"

    def log_message(self, format: str, *args) -> None:  # noqa: A002 - the base class's name
        sys.stderr.write(f"tidyplan serve: {self.address_string()} {format % args}\n")

    def _send(self, code: int, body: dict) -> None:
        data = json.dumps(body).encode()
        self.send_response(code)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        with contextlib.suppress(BrokenPipeError, ConnectionResetError):
            self.wfile.write(data)

    def do_GET(self) -> None:  # noqa: N802 - http.server's name
        self._send(405, {"status": "error", "result": {"error": "POST /solve"}})

    def do_POST(self) -> None:  # noqa: N802 - http.server's name
        url = urlparse(self.path)
        if url.path.rstrip("/") != "/solve":
            self._send(404, {"status": "error", "result": {"error": f"no {url.path}: POST /solve"}})
            return
        try:
            size = int(self.headers.get("Content-Length") or 0)
            if not 0 < size <= _MAX_BODY:
                raise BadRequest("a JSON body is needed (at most 64 MB)")
            try:
                body = json.loads(self.rfile.read(size).decode("utf-8"))
            except (UnicodeDecodeError, json.JSONDecodeError) as e:
                raise BadRequest(f"the body is not JSON: {e}") from None
            if not isinstance(body, dict):
                raise BadRequest('the body must be {"domain": text, "problem": text}')
            answer = self.service.solve(body, url.query)
        except (BadRequest, ValueError) as e:
            answer = {"status": "error", "result": {"output": "", "error": str(e)}}
        except Exception as e:  # noqa: BLE001 - one request's fault is its own reply
            answer = {"status": "error", "result": {"output": "", "error": f"internal error: {e}"}}
        self._send(200, answer)


def make_server(host: str, port: int, limit: float = DEFAULT_LIMIT) -> tuple[ThreadingHTTPServer, Service]:
    service = Service(limit)
    handler = type("Handler", (_Handler,), {"service": service})
    httpd = ThreadingHTTPServer((host, port), handler)
    httpd.daemon_threads = True
    return httpd, service


def _subreaper() -> None:
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)


def serve(host: str, port: int, limit: float = DEFAULT_LIMIT) -> int:
    """Serve until interrupted (Ctrl-C, SIGTERM); every request's planner is ended first."""
    _subreaper()
    httpd, service = make_server(host, port, limit)
    h, p = httpd.server_address[:2]
    print(f"tidyplan serve: POST http://{h}:{p}/solve (planning limit {limit:g} s)", flush=True)

    # SIGTERM and SIGHUP end the loop as Ctrl-C does, from a thread (`shutdown` waits for it)
    def stop(_signum, _frame) -> None:
        threading.Thread(target=httpd.shutdown, daemon=True).start()

    previous = {sig: signal.signal(sig, stop) for sig in (signal.SIGTERM, signal.SIGHUP)}
    try:
        httpd.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        service.stop()
        httpd.server_close()
        service.reap_orphans()
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    return 0
