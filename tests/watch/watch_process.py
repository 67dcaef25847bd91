"""Starts `snell watch` on a scene with --port 0 and reads the URL it prints; stops it
by its PID (SIGTERM, then SIGKILL). Shared by the watch tests and scripts/screenshots.sh."""

import json
import os
import select
import signal
import subprocess
import tempfile
import time
import urllib.request


class SnellWatch:
    def __init__(self, snell, scene, *args):
        self.log = tempfile.NamedTemporaryFile(prefix="snell-watch-", suffix=".log", delete=False)
        self.proc = subprocess.Popen([snell, "watch", scene, "--port", "0", *args],
                                     stdout=subprocess.PIPE, stderr=self.log)
        ready, _, _ = select.select([self.proc.stdout], [], [], 20)
        line = self.proc.stdout.readline().decode().strip() if ready else ""
        if not line.startswith("http://127.0.0.1:"):
            self.stop()
            raise RuntimeError(f"snell watch printed no URL (got {line!r}); log:\n{self.text()}")
        self.url = line

    def get(self, path):
        with urllib.request.urlopen(self.url.rstrip("/") + path, timeout=10) as r:
            return r.read()

    def state(self):
        return json.loads(self.get("/state"))

    def wait_state(self, pred, timeout=30, what="a state"):
        end = time.time() + timeout
        s = None
        while time.time() < end:
            s = self.state()
            if pred(s):
                return s
            time.sleep(0.05)
        raise AssertionError(f"timed out waiting for {what}; last state {s}; log:\n{self.text()}")

    def text(self):
        self.log.flush()
        with open(self.log.name, errors="replace") as f:
            return f.read()

    def stop(self):
        """SIGTERM, as a user's Ctrl-C would; the exit code is returned (0 expected)."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
                return None
        os.unlink(self.log.name)
        return self.proc.returncode


def save_like_an_editor(path, text):
    """Writes a new file beside `path` and renames it over `path` (vim, VS Code, sed -i):
    the old inode goes, so the watch must be on the folder."""
    tmp = path + ".tmp~"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
