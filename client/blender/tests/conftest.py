"""A real farm for the add-on's end-to-end test: `farm coordinator` and two `farm-worker`
processes from $FARM_BIN_DIR, authenticated with random tokens, in a temporary folder."""

import atexit
import os
import secrets
import shutil
import subprocess
import tempfile
import threading
import time

import pytest

# Blender's user folders (where the add-on installer puts add-ons, and the preferences),
# kept apart from the user's own: bpy reads these when it is first imported, which is
# after conftest.
_USER = tempfile.mkdtemp(prefix="photonfarm-blender-user-")
atexit.register(shutil.rmtree, _USER, ignore_errors=True)
os.environ["BLENDER_USER_RESOURCES"] = _USER
os.environ["BLENDER_USER_SCRIPTS"] = os.path.join(_USER, "scripts")


def _bin(name):
    folder = os.environ.get("FARM_BIN_DIR")
    if not folder:
        pytest.fail("FARM_BIN_DIR must name the folder of farm and farm-worker (make test-blender sets it)")
    path = os.path.join(folder, name)
    if not os.access(path, os.X_OK):
        pytest.fail(f"{path} is not an executable")
    return path


class Farm:
    def __init__(self, farm, address, token):
        self.farm, self.address, self.token = farm, address, token


@pytest.fixture(scope="session")
def farm(tmp_path_factory):
    root = tmp_path_factory.mktemp("farm")
    client, worker = secrets.token_hex(16), secrets.token_hex(16)
    (root / "client.tokens").write_text(client + "\n")
    (root / "worker.tokens").write_text(worker + "\n")
    coordinator = subprocess.Popen(
        [_bin("farm"), "coordinator", "--listen", "127.0.0.1:0", "--data-dir", str(root / "data"),
         "--client-token-file", str(root / "client.tokens"),
         "--worker-token-file", str(root / "worker.tokens")],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    found = []

    def read():
        for line in coordinator.stderr:
            if not found and "coordinator listening on " in line:
                found.append(line.split("coordinator listening on ", 1)[1].split()[0])
    threading.Thread(target=read, daemon=True).start()
    deadline = time.monotonic() + 15
    while not found and time.monotonic() < deadline and coordinator.poll() is None:
        time.sleep(0.05)
    processes = [coordinator]
    try:
        if not found:
            pytest.fail("the coordinator did not say `coordinator listening on` within 15 s")
        env = dict(os.environ, FARM_WORKER_TOKEN=worker)
        for i in range(2):
            processes.append(subprocess.Popen(
                [_bin("farm-worker"), "--coordinator", found[0], "--threads", "1",
                 "--name", f"blender-test-{i}", "--cache-dir", str(root / f"cache{i}")],
                env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        yield Farm(_bin("farm"), found[0], client)
    finally:
        for p in reversed(processes):
            p.terminate()
        for p in reversed(processes):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
