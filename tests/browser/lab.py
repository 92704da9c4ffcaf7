"""A JupyterLab server for tests: private config, temp XDG dirs, a token, stopped with SIGINT twice.

The server runs ``python -m jupyterlab`` of this interpreter on 127.0.0.1 at a free port, in its
own process group (its kernels too), so ``stop()`` can leave no process behind.
"""

from __future__ import annotations

import contextlib
import json
import os
import secrets
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

# Extensions that would fetch news or pop up notices over the notebook in a fresh profile.
DISABLED_EXTENSIONS = {"@jupyterlab/apputils-extension:announcements": True}


def processes_mentioning(text: str) -> list[int]:
    """Pids of live processes whose command line contains ``text`` (a temp dir of ours): none may outlive a test."""
    pids = []
    for proc in Path("/proc").glob("[0-9]*"):
        try:
            cmdline = (proc / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            state = next((ln for ln in (proc / "status").read_text().splitlines() if ln.startswith("State:")), "")
        except OSError:
            continue
        if text in cmdline and int(proc.name) != os.getpid() and "zombie" not in state:
            pids.append(int(proc.name))
    return pids


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LabServer:
    """``with LabServer(root_dir, work_dir) as lab:`` serves ``root_dir``; ``lab.url(path)`` adds the token.

    ``work_dir`` (empty, temporary) holds the private Jupyter config, XDG dirs and the server log.
    ``pythonpath`` is put first on the kernels' ``PYTHONPATH`` (so they import this checkout).
    """

    def __init__(self, root_dir: Path, work_dir: Path, pythonpath: Path | None = None, start_timeout: float = 300.0):
        self.root_dir, self.work_dir = Path(root_dir), Path(work_dir)
        self.pythonpath = pythonpath
        self.start_timeout = start_timeout  # a guard against a server that never answers: seconds idle, minutes loaded
        self.port = free_port()
        self.token = secrets.token_hex(16)
        self.base = f"http://127.0.0.1:{self.port}"
        self.proc: subprocess.Popen | None = None
        self.log_path = self.work_dir / "jupyterlab.log"

    def url(self, path: str = "", **query: str) -> str:
        params = "&".join([f"token={self.token}", *(k if v == "" else f"{k}={v}" for k, v in query.items())])
        return f"{self.base}/{path.lstrip('/')}?{params}"

    def _env(self) -> dict[str, str]:
        config = self.work_dir / "jupyter_config"
        (config / "labconfig").mkdir(parents=True, exist_ok=True)
        page_config = {"disabledExtensions": DISABLED_EXTENSIONS}
        (config / "labconfig" / "page_config.json").write_text(json.dumps(page_config))
        env = dict(os.environ)
        env.update(
            JUPYTER_CONFIG_DIR=str(config),
            JUPYTER_RUNTIME_DIR=str(self.work_dir / "runtime"),
            JUPYTER_DATA_DIR=str(self.work_dir / "data"),  # no user kernelspec can replace this interpreter's
            IPYTHONDIR=str(self.work_dir / "ipython"),  # no user profile or startup files
            JUPYTERLAB_WORKSPACES_DIR=str(self.work_dir / "workspaces"),
            XDG_CACHE_HOME=str(self.work_dir / "xdg_cache"),
            XDG_CONFIG_HOME=str(self.work_dir / "xdg_config"),
            PYTHONUNBUFFERED="1",
        )
        if self.pythonpath is not None:
            env["PYTHONPATH"] = os.pathsep.join(p for p in (str(self.pythonpath), env.get("PYTHONPATH", "")) if p)
        return env

    def start(self) -> LabServer:
        cmd = [
            sys.executable, "-m", "jupyterlab", "--no-browser", "--allow-root",
            "--ip=127.0.0.1", f"--port={self.port}", "--port-retries=0",
            f"--IdentityProvider.token={self.token}", f"--ServerApp.root_dir={self.root_dir}",
            "--LabApp.news_url=None", "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate",
            "--LabApp.expose_app_in_browser=True",
        ]  # fmt: skip
        log = self.log_path.open("wb")
        self.proc = subprocess.Popen(
            cmd, env=self._env(), cwd=self.root_dir, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
            start_new_session=True,
        )  # fmt: skip
        log.close()
        try:
            self._wait_ready()
        except BaseException:
            self.stop()
            raise
        return self

    def _wait_ready(self) -> None:
        deadline = time.monotonic() + self.start_timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"JupyterLab exited with code {self.proc.returncode}:\n{self.log_tail()}")
            try:
                with urllib.request.urlopen(f"{self.base}/api/status?token={self.token}", timeout=30) as r:
                    if r.status == 200:
                        return
            except (urllib.error.URLError, ConnectionError, TimeoutError):
                pass
            time.sleep(0.25)
        raise TimeoutError(f"JupyterLab did not answer /api/status within {self.start_timeout} s:\n{self.log_tail()}")

    def log_tail(self, n: int = 40) -> str:
        try:
            return "\n".join(self.log_path.read_text(errors="replace").splitlines()[-n:])
        except OSError:
            return "(no log)"

    def _api(self, method: str, path: str) -> object:
        req = urllib.request.Request(f"{self.base}/api/{path}?token={self.token}", method=method)
        with urllib.request.urlopen(req, timeout=120) as r:  # a busy server answers late, not never
            body = r.read()
        return json.loads(body) if body else None

    def shutdown_kernels(self) -> None:
        """Shut every kernel down through the REST API (kernels run in their own sessions, outside our group)."""
        for kernel in self._api("GET", "kernels"):
            with contextlib.suppress(urllib.error.HTTPError):
                self._api("DELETE", f"kernels/{kernel['id']}")

    def shutdown_sessions(self) -> None:
        """End every notebook session and its kernel: the next page opening a notebook starts a new kernel."""
        for session in self._api("GET", "sessions"):
            with contextlib.suppress(urllib.error.HTTPError):
                self._api("DELETE", f"sessions/{session['id']}")
        self.shutdown_kernels()

    def stop(self) -> None:
        """Kernels first, then SIGINT twice (the server asks to confirm the first), then SIGKILL what is left."""
        proc, self.proc = self.proc, None
        if proc is None:
            return
        if proc.poll() is None:
            with contextlib.suppress(OSError, ValueError):
                self.shutdown_kernels()
        pgid = proc.pid  # start_new_session: the server leads its own process group
        for _ in range(2):
            if proc.poll() is not None:
                break
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                continue
        if proc.poll() is None:
            proc.kill()
            proc.wait(timeout=10)
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(pgid, signal.SIGKILL)
        # A kernel still shutting down names its connection file, under our runtime dir.
        deadline = time.monotonic() + 10
        while (left := processes_mentioning(str(self.work_dir))) and time.monotonic() < deadline:
            time.sleep(0.2)
        for pid in left:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)

    def __enter__(self) -> LabServer:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
