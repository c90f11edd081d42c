"""Runs the farm's command-line tool (`farm submit --watch`, then `farm fetch`) as a
subprocess and reads its progress. No bpy here: the add-on's modal operator and the
headless render() both drive a FarmRun.

The coordinator is --coordinator (else the CLI's own $FARM_COORDINATOR / localhost:7070);
a client token goes in $FARM_TOKEN, never on the command line, where other users of the
machine could read it."""

import os
import queue
import re
import subprocess
import threading

_PERCENT = re.compile(r"(\d{1,3})%")


def progress_fraction(line):
    """The fraction done that a line of the CLI's progress shows (its last "NN%"), or None
    for a line without one."""
    found = _PERCENT.findall(line)
    if not found:
        return None
    return min(100, int(found[-1])) / 100.0


def _environment(token):
    env = dict(os.environ)
    if token:
        env["FARM_TOKEN"] = token
    return env


def _coordinator_flags(coordinator):
    return ["--coordinator", coordinator] if coordinator else []


class FarmError(RuntimeError):
    pass


class FarmRun:
    """One submission: `farm submit SCENE --watch` in the background, its output lines
    queued for poll(), then `farm fetch` once it succeeded."""

    def __init__(self, farm, scene_path, coordinator=None, token=None):
        self.farm, self.coordinator, self.token = farm, coordinator, token
        self.job_id = None
        self.fraction = 0.0
        self.last_line = ""
        self.lines = []
        self._queue = queue.Queue()
        self._process = subprocess.Popen(
            [farm, "submit", scene_path, "--watch"] + _coordinator_flags(coordinator),
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
            text=True, env=_environment(token))
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        for line in self._process.stdout:
            self._queue.put(line.rstrip("\n"))
        self._queue.put(None)

    def poll(self):
        """Takes in the lines printed since the last call. Returns None while the CLI runs,
        else its exit status (once every line has been taken in)."""
        while True:
            try:
                line = self._queue.get_nowait()
            except queue.Empty:
                return None
            if line is None:
                return self._process.wait()
            self._take(line)

    def _take(self, line):
        self.lines.append(line)
        if self.job_id is None and line and " " not in line.strip():
            self.job_id = line.strip()  # farm submit prints the job id alone first
            return
        fraction = progress_fraction(line)
        if fraction is not None:
            self.fraction = fraction
        if line.strip():
            self.last_line = line.strip()

    def wait(self, on_line=None):
        """Blocks until the CLI ends; on_line sees each line. Returns its exit status."""
        while True:
            line = self._queue.get()
            if line is None:
                return self._process.wait()
            self._take(line)
            if on_line:
                on_line(line)

    def cancel(self):
        if self._process.poll() is None:
            self._process.terminate()
        if self.job_id:
            subprocess.run([self.farm, "cancel", self.job_id] + _coordinator_flags(self.coordinator),
                           env=_environment(self.token), capture_output=True, timeout=30)

    def failure(self, status):
        tail = "\n".join(self.lines[-5:])
        return FarmError(f"farm submit exited with status {status}:\n{tail}")

    def fetch(self, out_dir, name):
        """Downloads the finished job's image. Returns the paths of NAME.exr and NAME.png."""
        done = subprocess.run(
            [self.farm, "fetch", self.job_id, "-o", out_dir, "--name", name] + _coordinator_flags(self.coordinator),
            env=_environment(self.token), capture_output=True, text=True, timeout=600)
        if done.returncode != 0:
            raise FarmError(f"farm fetch {self.job_id} failed: {done.stdout}{done.stderr}".strip())
        return os.path.join(out_dir, name + ".exr"), os.path.join(out_dir, name + ".png")
