"""A real farm for the tests: a `farm coordinator` process with client and worker tokens,
serving TLS with a self-signed certificate (made by openssl), and one `farm-worker`, both
from $FARM_BIN_DIR. Without the binaries the tests fail, never skip (tests/README.md)."""

from __future__ import annotations

import dataclasses
import os
import pathlib
import signal
import socket
import subprocess
import time

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
CLIENT_TOKEN = "python-sdk-client-token"
WORKER_TOKEN = "python-sdk-worker-token"
LOG_TAIL_LINES = 40


@dataclasses.dataclass
class Farm:
    address: str
    ca_file: pathlib.Path  # the coordinator's self-signed certificate, its own CA
    logs: list[pathlib.Path]


def _bin_dir() -> pathlib.Path:
    d = os.environ.get("FARM_BIN_DIR")
    if not d:
        pytest.fail("FARM_BIN_DIR is not set: these tests run the built binaries. Build them (make build) "
                    "and run FARM_BIN_DIR=$PWD/build/bin pytest client/python/tests, or run make test-python")
    d = pathlib.Path(d).resolve()
    for b in ("farm", "farm-worker"):
        if not (d / b).is_file():
            pytest.fail(f"FARM_BIN_DIR={d}: no {b} (build with make build)")
    return d


def _self_signed(dir: pathlib.Path) -> tuple[pathlib.Path, pathlib.Path]:
    cert, key = dir / "cert.pem", dir / "key.pem"
    subprocess.run(["openssl", "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:P-256",
                    "-nodes", "-days", "1", "-subj", "/CN=photonfarm python test coordinator",
                    "-addext", "subjectAltName=IP:127.0.0.1,DNS:localhost",
                    "-keyout", str(key), "-out", str(cert)], check=True, capture_output=True)
    return cert, key


def _start(cmd: list[str], log: pathlib.Path, env: dict[str, str] | None = None) -> subprocess.Popen:
    """Starts cmd in a process group of its own, its output in log."""
    with open(log, "wb") as out:
        return subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                start_new_session=True, env=env)


def _listening_address(proc: subprocess.Popen, log: pathlib.Path, within: float = 15.0) -> str:
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        for line in log.read_text(errors="replace").splitlines():
            if "coordinator listening on " in line:
                return line.split("coordinator listening on ", 1)[1].strip()
        if proc.poll() is not None:
            pytest.fail(f"the coordinator exited ({proc.returncode}) before listening:\n{log.read_text()}")
        time.sleep(0.05)
    pytest.fail(f"the coordinator did not say `coordinator listening on` within {within} s:\n{log.read_text()}")


@pytest.fixture(scope="session")
def farm(tmp_path_factory: pytest.TempPathFactory):
    bin_dir = _bin_dir()
    tmp = tmp_path_factory.mktemp("farm")
    cert, key = _self_signed(tmp)
    (tmp / "client-tokens").write_text(CLIENT_TOKEN + "\n")
    (tmp / "worker-tokens").write_text(WORKER_TOKEN + "\n")
    procs: list[subprocess.Popen] = []
    logs = [tmp / "coordinator.log", tmp / "worker.log"]
    try:
        coordinator = _start([str(bin_dir / "farm"), "coordinator", "--listen", "127.0.0.1:0",
                              "--lease-duration", "2s", "--data-dir", str(tmp / "data"),
                              "--client-token-file", str(tmp / "client-tokens"),
                              "--worker-token-file", str(tmp / "worker-tokens"),
                              "--tls-cert", str(cert), "--tls-key", str(key)], logs[0])
        procs.append(coordinator)
        address = _listening_address(coordinator, logs[0])
        procs.append(_start([str(bin_dir / "farm-worker"), "--coordinator", address, "--tls-ca", str(cert),
                             "--cache-dir", str(tmp / "cache"), "--threads", "1", "--name", "python-test-worker"],
                            logs[1], env={**os.environ, "FARM_WORKER_TOKEN": WORKER_TOKEN}))
        yield Farm(address=address, ca_file=cert, logs=logs)
    finally:
        for p in procs:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item, call):
    report = yield
    setattr(item, "report_" + report.when, report)
    return report


@pytest.fixture(autouse=True)
def farm_logs_on_failure(request: pytest.FixtureRequest):
    """Prints the last lines of the farm's logs after a test that used it failed."""
    yield
    report = getattr(request.node, "report_call", None)
    if report is None or not report.failed or "farm" not in request.fixturenames:
        return
    for log in request.getfixturevalue("farm").logs:
        lines = log.read_text(errors="replace").splitlines()[-LOG_TAIL_LINES:]
        print(f"--- last lines of {log.name} ---", *lines, sep="\n")


@pytest.fixture
def unused_address() -> str:
    """A loopback address where nothing listens."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return "127.0.0.1:%d" % s.getsockname()[1]
