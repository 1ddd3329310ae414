"""A warm worker process that answers quick ``rrbody`` calls without paying numba's start-up.

Why: a new Python process pays about 1.1 s before its first cached numba kernel runs (``make
bench``, study ``startup``; a cProfile of one call puts ~0.3 s in importing numba and ~0.6 s in
setting up its compilation target, scipy.linalg included), while ``rrbody flip-time`` solves in a
few milliseconds.

How: the first ``rrbody flip-time`` / ``critical-h`` / ``simulate`` runs in its own process as
usual, then starts a worker in the background. The worker imports rrbody, loads the compiled
kernels once, and listens on a Unix socket in a private folder (mode 0700). Later calls connect,
pass their own stdin/stdout/stderr file descriptors (SCM_RIGHTS), working directory, umask,
environment and arguments; the worker forks a child that runs exactly the in-process command
(``rrbody.cli.main``) on those descriptors, so output, progress bars, relative paths and exit
codes are those of a normal run. Ctrl-C and other signals are forwarded to the child.

Safety rules:

- A worker serves one installation and one environment: its socket name is a hash of the
  package's source files (path, size, mtime), the interpreter, and the environment variables
  read at import time (``NUMBA_*``, ``PYTHON*``, ``MPL*``, ``OMP_*``, ``OPENBLAS_*``). Editing
  rrbody or changing those variables starts a new worker; the old one exits when idle.
- It exits after ``RRBODY_WORKER_IDLE`` seconds without a request (default 900).
- Any doubt (no worker yet, a stale socket, a busy or broken worker, closed standard streams,
  no Unix sockets) means the call runs in-process, exactly as without a worker.
- ``RRBODY_WORKER=off`` turns the worker off; ``rrbody worker status|start|stop`` manage it.
"""

from __future__ import annotations

# Only what a forwarding call needs is imported here: every `rrbody` call imports this module.
import argparse
import contextlib
import fcntl
import hashlib
import json
import os
import signal
import socket
import stat
import struct
import sys
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, NamedTuple, NoReturn

__all__ = ["SERVED", "WorkerSettings", "settings", "forward", "spawn", "ping", "stop", "serve", "add_parser"]

#: subcommands a worker answers: the quick queries, where start-up dominates the cost
SERVED = frozenset({"flip-time", "critical-h", "simulate"})
DEFAULT_IDLE_S = 900.0
MAX_IDLE_S = 7 * 24 * 3600.0
#: environment variables that modules read when imported: a worker only serves callers that agree
_FINGERPRINT_PREFIXES = ("NUMBA_", "PYTHON", "MPL", "OMP_", "OPENBLAS_", "MKL_")
_HEADER = struct.Struct("!Q")
_MAX_REQUEST = 16 * 1024 * 1024
_PACKAGE_DIR = Path(__file__).resolve().parent
#: macOS limits AF_UNIX paths to 104 bytes (Linux: 108)
_MAX_SOCKET_PATH = 100


class WorkerSettings(NamedTuple):
    """Where the worker for this installation and environment lives, and how long it idles."""

    folder: Path
    key: str
    idle_s: float

    @property
    def socket(self) -> Path:
        return self.folder / f"{self.key}.sock"

    @property
    def lock(self) -> Path:
        return self.folder / f"{self.key}.lock"

    @property
    def log(self) -> Path:
        return self.folder / f"{self.key}.log"


def _supported() -> bool:
    return os.name == "posix" and hasattr(socket, "AF_UNIX") and hasattr(socket, "send_fds")


def fingerprint(environ: Mapping[str, str]) -> str:
    """Hash of what a warm worker has baked in: rrbody's sources, the interpreter, import-time env."""
    h = hashlib.sha256()
    h.update(f"{sys.executable}\0{sys.version}\0{_PACKAGE_DIR}\0".encode())
    for root, dirs, files in os.walk(_PACKAGE_DIR):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            if name.endswith(".py"):
                st = os.stat(os.path.join(root, name))
                h.update(f"{os.path.relpath(os.path.join(root, name), _PACKAGE_DIR)}\0{st.st_size}\0"
                         f"{st.st_mtime_ns}\0".encode())
    for k in sorted(environ):
        if k.startswith(_FINGERPRINT_PREFIXES):
            h.update(f"{k}={environ[k]}\0".encode())
    return h.hexdigest()[:16]


def _folder(environ: Mapping[str, str]) -> Path:
    if environ.get("RRBODY_WORKER_DIR"):
        return Path(environ["RRBODY_WORKER_DIR"])
    if environ.get("XDG_RUNTIME_DIR"):
        return Path(environ["XDG_RUNTIME_DIR"]) / "rrbody"
    import tempfile

    return Path(tempfile.gettempdir()) / f"rrbody-{os.getuid()}"


def _private_folder(path: Path) -> bool:
    """Create ``path`` (mode 0700) and check nobody else can use it: other users must not be able
    to reach our worker, nor plant a socket that we would talk to."""
    try:
        path.mkdir(mode=0o700, parents=True, exist_ok=True)
        st = path.lstat()
    except OSError:
        return False
    return stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid() and not st.st_mode & 0o077


def settings(environ: Mapping[str, str] = os.environ) -> WorkerSettings | None:
    """The worker settings, or None when the worker is off or cannot be used here.

    Raises ValueError naming ``RRBODY_WORKER`` or ``RRBODY_WORKER_IDLE`` for a bad value.
    """
    switch = environ.get("RRBODY_WORKER", "on").strip().lower()
    if switch not in ("on", "off", "1", "0"):
        raise ValueError(f"RRBODY_WORKER must be 'on' or 'off' (or 1/0), got {environ['RRBODY_WORKER']!r}")
    text = environ.get("RRBODY_WORKER_IDLE", "")
    idle = DEFAULT_IDLE_S
    if text:
        try:
            idle = float(text)
        except ValueError:
            idle = float("nan")
        if not 0.0 < idle <= MAX_IDLE_S:
            raise ValueError(f"RRBODY_WORKER_IDLE must be seconds in (0, {MAX_IDLE_S:g}], got {text!r}")
    if switch in ("off", "0") or not _supported():
        return None
    folder = _folder(environ)
    s = WorkerSettings(folder, fingerprint(environ), idle)
    if len(os.fsencode(s.socket)) > _MAX_SOCKET_PATH or not _private_folder(folder):
        return None
    return s


# ---- client side -----------------------------------------------------------------------------
def _connect(s: WorkerSettings, timeout: float) -> socket.socket | None:
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    sock.settimeout(timeout)
    try:
        sock.connect(os.fspath(s.socket))
    except OSError:
        sock.close()
        return None
    return sock


def _send(sock: socket.socket, request: dict[str, Any], fds: Sequence[int] = ()) -> None:
    payload = json.dumps(request).encode()
    socket.send_fds(sock, [_HEADER.pack(len(payload))], list(fds))
    sock.sendall(payload)


def _reply(sock: socket.socket, request: dict[str, Any], timeout: float) -> dict[str, Any] | None:
    """Send a control request (ping, stop) and read the one-line answer; None if no worker."""
    try:
        _send(sock, request)
        sock.settimeout(timeout)
        line = sock.makefile("rb").readline()
        return json.loads(line) if line else None
    except (OSError, ValueError):
        return None
    finally:
        sock.close()


def ping(s: WorkerSettings, timeout: float = 2.0) -> dict[str, Any] | None:
    """Status of the running worker (pid, requests served, idle timeout, ...), or None."""
    sock = _connect(s, timeout)
    return None if sock is None else _reply(sock, {"op": "ping"}, timeout)


def stop(s: WorkerSettings, timeout: float = 5.0) -> bool:
    """Ask the worker to exit; True once its socket is gone (False if none was running)."""
    sock = _connect(s, timeout)
    if sock is None or _reply(sock, {"op": "stop"}, timeout) is None:
        return False
    deadline = time.monotonic() + timeout
    while s.socket.exists() and time.monotonic() < deadline:
        time.sleep(0.02)
    return not s.socket.exists()


def _take_lock(path: Path) -> int | None:
    """The descriptor holding ``path``'s exclusive lock, or None if a worker holds it already.
    The lock lasts while the descriptor is open (in any process that inherited it)."""
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        return None
    return fd


def _starting(s: WorkerSettings) -> bool:
    """True if a worker holds the lock (it is warming up or serving)."""
    try:
        fd = _take_lock(s.lock)
    except OSError:
        return True  # cannot tell: do not start another
    if fd is None:
        return True
    os.close(fd)  # releases the lock we just took
    return False


def spawn(s: WorkerSettings, environ: Mapping[str, str] = os.environ) -> bool:
    """Start a worker in the background (its own session, no terminal) unless one is running or
    warming up. Returns True if a new worker process was started."""
    import subprocess

    if _starting(s):
        return False
    env = dict(environ)
    # the worker must import this very rrbody, whatever the caller's working directory was
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(_PACKAGE_DIR.parent), environ.get("PYTHONPATH")) if p)
    with contextlib.suppress(OSError):
        if s.log.stat().st_size > 1_000_000:
            s.log.unlink()
    try:
        with os.fdopen(os.open(s.log, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600), "ab") as log:
            subprocess.Popen([sys.executable, "-m", "rrbody.worker", "--socket", os.fspath(s.socket),
                              "--lock", os.fspath(s.lock), "--idle", repr(s.idle_s),
                              "--package-dir", str(_PACKAGE_DIR)],
                             stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT, cwd="/",
                             env=env, start_new_session=True, close_fds=True)
    except OSError:
        return False
    return True


def _streams_open() -> bool:
    try:
        for fd in (0, 1, 2):
            os.fstat(fd)
    except OSError:
        return False
    return True


def forward(argv: Sequence[str], s: WorkerSettings) -> int | None:
    """Run ``rrbody ARGV`` in the warm worker and return its exit code; None when no worker took
    the call (then nothing has run and the caller runs it in-process)."""
    if not argv or argv[0] not in SERVED or not _streams_open():
        return None
    sock = _connect(s, timeout=1.0)
    if sock is None:
        return None
    mask = os.umask(0)
    os.umask(mask)
    request = {"op": "run", "argv": list(argv), "cwd": os.getcwd(), "env": dict(os.environ), "umask": mask}
    try:
        _send(sock, request, fds=(0, 1, 2))
        sock.settimeout(10.0)  # the worker forks at once: no answer means it is wedged
        lines = sock.makefile("rb")
        started = lines.readline()
        if not started or "started" not in json.loads(started):
            raise ValueError("no start")
    except (OSError, ValueError):
        sock.close()
        return None
    except KeyboardInterrupt:  # Ctrl-C before the run began: the worker sees us hang up and stops it
        from rrbody.cli import INTERRUPTED

        sock.close()
        print(INTERRUPTED, file=sys.stderr)
        return 130
    sock.settimeout(None)
    forwarded: list[int] = []

    def relay(signum: int, _frame: object) -> None:
        forwarded.append(signum)
        with contextlib.suppress(OSError):
            sock.sendall(json.dumps({"signal": signum}).encode() + b"\n")

    relayed = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT)
    previous = {sig: signal.signal(sig, relay) for sig in relayed}
    try:
        line = lines.readline()
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        sock.close()
    if line:
        return int(json.loads(line)["exit"])
    if forwarded:  # the child died of the signal we passed on: die of it too, as a plain run would
        signal.signal(forwarded[-1], signal.SIG_DFL)
        os.kill(os.getpid(), forwarded[-1])
    print(f"rrbody: the worker ended without an exit status; see {s.log}, or run with RRBODY_WORKER=off",
          file=sys.stderr)
    return 1


# ---- worker side -----------------------------------------------------------------------------
def _recv_request(conn: socket.socket) -> tuple[dict[str, Any], list[int]]:
    head, fds, _flags, _addr = socket.recv_fds(conn, _HEADER.size, 3)
    while len(head) < _HEADER.size:
        more = conn.recv(_HEADER.size - len(head))
        if not more:
            raise ConnectionError("truncated request")
        head += more
    (n,) = _HEADER.unpack(head)
    if n > _MAX_REQUEST:
        raise ConnectionError(f"request of {n} bytes")
    buf = bytearray()
    while len(buf) < n:
        more = conn.recv(min(65536, n - len(buf)))
        if not more:
            raise ConnectionError("truncated request")
        buf += more
    return json.loads(buf), fds


def _same_user(conn: socket.socket) -> bool:
    if not hasattr(socket, "SO_PEERCRED"):
        return True  # the 0700 folder already keeps other users out
    creds = conn.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, struct.calcsize("3i"))
    _pid, uid, _gid = struct.unpack("3i", creds)
    return uid == os.getuid()


def _text_stream(fd: int, mode: str, *, line_buffered: bool) -> Any:
    return open(fd, mode, buffering=1 if line_buffered else -1, encoding="utf-8",
                errors="backslashreplace" if fd == 2 else "strict", closefd=False)


def _run_child(conn: socket.socket, request: dict[str, Any], fds: list[int]) -> NoReturn:
    """In the forked child: become the caller's process, run the command, send its exit code.
    Never returns (the caller wraps it in ``os._exit`` as well, should anything escape)."""
    import threading
    import traceback

    code = 1
    try:
        for sig in (signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT, signal.SIGCHLD):
            signal.signal(sig, signal.SIG_DFL)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        os.environ.clear()
        os.environ.update(request["env"])
        os.chdir(request["cwd"])
        os.umask(int(request["umask"]))
        for target, fd in enumerate(fds):
            os.dup2(fd, target)
            os.close(fd)
        # what CPython builds at start-up: stdout line buffered on a terminal, stderr always
        sys.stdin = _text_stream(0, "r", line_buffered=False)
        sys.stdout = _text_stream(1, "w", line_buffered=os.isatty(1))
        sys.stderr = _text_stream(2, "w", line_buffered=True)
        sys.argv = ["rrbody", *request["argv"]]
        try:
            conn.sendall(json.dumps({"started": os.getpid()}).encode() + b"\n")
        except OSError:
            os._exit(0)  # the caller gave up before we began: it runs the command itself

        def watch() -> None:  # signals relayed by the caller; its disappearance counts as Ctrl-C
            for line in conn.makefile("rb"):
                with contextlib.suppress(ValueError, KeyError, OSError):
                    os.kill(os.getpid(), int(json.loads(line)["signal"]))
            os.kill(os.getpid(), signal.SIGINT)

        threading.Thread(target=watch, daemon=True).start()
        from rrbody.cli import main

        try:
            code = int(main(request["argv"]) or 0)
        except SystemExit as e:  # argparse: --help, --version, usage errors
            if e.code is None or isinstance(e.code, int):
                code = int(e.code or 0)
            else:
                print(e.code, file=sys.stderr)
                code = 1
        except KeyboardInterrupt:
            code = 130
        except BaseException:  # noqa: BLE001 - report like the interpreter would, then exit 1
            traceback.print_exc()
            code = 1
    finally:
        # the watcher turns the caller's hang-up into SIGINT: it must not interrupt the last words
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        with contextlib.suppress(OSError):
            conn.sendall(json.dumps({"exit": code}).encode() + b"\n")
        os._exit(0)


def _warm_up() -> None:
    """Import the served commands and load their compiled kernels (from numba's cache) once."""
    import io

    from rrbody.cli import main

    calls = [["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--json"],
             ["flip-time", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--friction", "viscous", "--json"],
             ["flip-time", "--H", "0.2", "--k", "0", "--omega", "0.6", "--friction", "none", "--t-max", "5",
              "--json"],
             ["flip-time", "--body", "disk", "--R0", "0.1", "--l", "0.2", "--k", "0.05", "--omega", "0.6",
              "--t-max", "2", "--json"],
             ["critical-h", "--k", "0.01", "--omega", "0.3", "--tol", "1e-3", "--json"],
             ["simulate", "--H", "0.2", "--k", "0.05", "--omega", "0.6", "--t-max", "1", "--json"]]
    for argv in calls:
        sink = io.StringIO()
        try:
            with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
                main(argv)
        except BaseException as e:  # noqa: BLE001 - a failed warm-up only costs speed later
            print(f"warm-up {argv[0]} failed: {e!r}", file=sys.stderr)


def serve(sock_path: Path, lock_path: Path, idle_s: float, package_dir: Path | None = None) -> int:
    """The worker's main loop (run by ``spawn``); returns when idle for ``idle_s`` or stopped."""
    lock_fd = _take_lock(lock_path)
    if lock_fd is None:
        return 0  # another worker for the same key is up
    import rrbody

    if package_dir is not None and Path(rrbody.__file__).resolve().parent != package_dir.resolve():
        print(f"imported rrbody from {rrbody.__file__}, expected {package_dir}: not serving", file=sys.stderr)
        return 1
    t0 = time.monotonic()
    _warm_up()
    print(f"{time.strftime('%Y-%m-%d %H:%M:%S')} pid {os.getpid()} ready after {time.monotonic() - t0:.2f} s",
          file=sys.stderr, flush=True)
    with contextlib.suppress(FileNotFoundError):
        sock_path.unlink()  # stale: we hold the lock, so no live worker owns it
    srv = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    srv.bind(os.fspath(sock_path))
    os.chmod(sock_path, 0o600)
    inode = sock_path.stat().st_ino
    srv.listen(16)
    srv.settimeout(idle_s)

    def on_term(_signum: int, _frame: object) -> None:
        raise SystemExit(0)

    signal.signal(signal.SIGTERM, on_term)
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # children are reaped by the kernel
    served = 0
    started = time.time()
    try:
        while True:
            try:
                conn, _ = srv.accept()
            except TimeoutError:
                break
            with conn:
                fds: list[int] = []
                try:
                    conn.settimeout(5.0)
                    if not _same_user(conn):
                        continue
                    request, fds = _recv_request(conn)
                    op = request.get("op")
                    if op == "ping":
                        conn.sendall(json.dumps({"pid": os.getpid(), "served": served, "idle_s": idle_s,
                                                 "uptime_s": round(time.time() - started, 1),
                                                 "socket": os.fspath(sock_path),
                                                 "package": str(Path(rrbody.__file__).parent),
                                                 "version": rrbody.__version__}).encode() + b"\n")
                    elif op == "stop":
                        conn.sendall(b'{"stopping": true}\n')
                        break
                    elif op == "run" and len(fds) == 3:
                        conn.settimeout(None)
                        if os.fork() == 0:
                            try:  # the child must never return into this loop
                                srv.close()
                                os.close(lock_fd)  # a long run must not keep a new worker from starting
                                _run_child(conn, request, fds)
                            finally:
                                os._exit(1)
                        served += 1
                except (OSError, ValueError, KeyError):
                    continue
                finally:
                    for fd in fds:
                        with contextlib.suppress(OSError):
                            os.close(fd)
    finally:
        srv.close()
        with contextlib.suppress(OSError):
            if sock_path.stat().st_ino == inode:
                sock_path.unlink()
        os.close(lock_fd)
    return 0


# ---- `rrbody worker ...` ---------------------------------------------------------------------
def _cmd_worker(args: argparse.Namespace) -> int:
    s = settings()
    if s is None:
        if args.action == "start":
            raise ValueError("RRBODY_WORKER is 'off' (or this system has no Unix sockets): no worker to start")
        status: dict[str, Any] = {"running": False, "enabled": False}
    else:
        if args.action == "stop":
            status = {"running": False, "enabled": True, "stopped": stop(s)}
        else:
            info = ping(s)
            if info is None and args.action == "start":
                spawn(s)
                deadline = time.monotonic() + 120.0
                while info is None and time.monotonic() < deadline:
                    time.sleep(0.1)
                    info = ping(s)
                if info is None:
                    raise ValueError(f"the worker did not start within 120 s; see {s.log}")
            status = {"running": info is not None, "enabled": True, **(info or {"socket": os.fspath(s.socket)})}
        status["log"] = os.fspath(s.log)
    if args.json:
        print(json.dumps(status))
    elif status.get("running"):
        print(f"worker running: pid {status['pid']}, {status['served']} requests served, up {status['uptime_s']} s, "
              f"exits after {status['idle_s']:g} s idle; socket {status['socket']}")
    elif not status.get("enabled"):
        print("worker off (RRBODY_WORKER=off): every call runs in its own process")
    else:
        print("worker stopped" if status.get("stopped") else "no worker running for this installation")
    return 0


def add_parser(sub: Any) -> None:
    """Register ``rrbody worker`` on the CLI's subparsers."""
    w = sub.add_parser("worker", help="the warm worker that answers quick calls fast: status, start, stop",
                       description=__doc__.split("\n\n")[0] + " See README: Fast repeated calls.")
    w.add_argument("action", choices=("status", "start", "stop"), nargs="?", default="status")
    w.add_argument("--json", action="store_true", help="print one JSON object")
    w.set_defaults(func=_cmd_worker)


def _main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m rrbody.worker", description="run a worker (started by rrbody)")
    p.add_argument("--socket", type=Path, required=True)
    p.add_argument("--lock", type=Path, required=True)
    p.add_argument("--idle", type=float, default=DEFAULT_IDLE_S)
    p.add_argument("--package-dir", type=Path, default=None)
    a = p.parse_args(argv)
    return serve(a.socket, a.lock, a.idle, a.package_dir)


if __name__ == "__main__":
    raise SystemExit(_main())
