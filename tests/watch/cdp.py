"""Headless Chromium driven over the DevTools protocol on a pipe (--remote-debugging-pipe:
requests on fd 3, answers on fd 4, each a JSON message ended by a NUL byte), so the
watch page tests need nothing beyond Debian's chromium and Python's standard library.
Used by test_page.py and scripts/screenshots.sh."""

import base64
import json
import os
import shutil
import subprocess
import tempfile
import time


def find_chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


class Chromium:
    def __init__(self, width=1280, height=800):
        exe = find_chromium()
        if not exe:
            raise RuntimeError("chromium is not installed (scripts/setup.sh test installs it)")
        self.profile = tempfile.mkdtemp(prefix="snell-chromium-")
        to_child_r, self.to_child = os.pipe()
        self.from_child, from_child_w = os.pipe()
        # Moved to high numbers first, so that the child's dup2 onto 3 and 4 never
        # meets its own source (the pipe ends may be 3 or 4 here).
        os.dup2(to_child_r, 200)
        os.dup2(from_child_w, 201)
        os.close(to_child_r)
        os.close(from_child_w)

        def child_fds():
            os.dup2(200, 3)
            os.dup2(201, 4)

        self.proc = subprocess.Popen(
            [exe, "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--disable-extensions", "--remote-debugging-pipe", f"--user-data-dir={self.profile}",
             f"--window-size={width},{height}", "about:blank"],
            preexec_fn=child_fds, close_fds=False,
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(200)
        os.close(201)
        self.next_id = 0
        self.buffer = b""
        self.session = None
        self.width, self.height = width, height

    def send(self, method, params=None, session=True, timeout=20):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self.to_child, json.dumps(msg).encode() + b"\0")
        end = time.time() + timeout
        while time.time() < end:
            answer = self._read(end - time.time())
            if answer is None:
                break
            if answer.get("id") == self.next_id:
                if "error" in answer:
                    raise RuntimeError(f"{method}: {answer['error']}")
                return answer.get("result", {})
        raise RuntimeError(f"{method}: no answer from chromium in {timeout} s")

    def _read(self, timeout):
        import select
        while b"\0" not in self.buffer:
            ready, _, _ = select.select([self.from_child], [], [], max(0.0, timeout))
            if not ready:
                return None
            chunk = os.read(self.from_child, 1 << 20)
            if not chunk:
                raise RuntimeError("chromium closed its DevTools pipe (did it crash?)")
            self.buffer += chunk
        raw, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(raw)

    def open(self, url):
        target = self.send("Target.createTarget", {"url": "about:blank"}, session=False)
        attached = self.send("Target.attachToTarget",
                             {"targetId": target["targetId"], "flatten": True}, session=False)
        self.session = attached["sessionId"]
        self.send("Emulation.setDeviceMetricsOverride",
                  {"width": self.width, "height": self.height, "deviceScaleFactor": 1,
                   "mobile": False})
        self.send("Page.navigate", {"url": url})
        # Page.navigate answers before the new document replaces about:blank.
        self.wait_for("location.href !== 'about:blank' && document.readyState !== 'loading' && "
                      "document.getElementById('image') !== null", what=f"{url} to load")

    def eval(self, expression):
        r = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        if "exceptionDetails" in r:
            raise RuntimeError(f"page script failed: {r['exceptionDetails']}")
        return r.get("result", {}).get("value")

    def wait_for(self, expression, timeout=20, what=None):
        """Polls a JS expression until it is truthy; returns its value."""
        end = time.time() + timeout
        value = None
        while time.time() < end:
            value = self.eval(expression)
            if value:
                return value
            time.sleep(0.1)
        raise AssertionError(f"timed out after {timeout} s waiting for {what or expression}; "
                             f"page: {self.eval(PAGE_STATE)}")

    def screenshot(self, path):
        r = self.send("Page.captureScreenshot", {"format": "png"})
        with open(path, "wb") as f:
            f.write(base64.b64decode(r["data"]))

    def close(self):
        try:
            self.send("Browser.close", session=False, timeout=5)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        for fd in (self.to_child, self.from_child):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self.profile, ignore_errors=True)


# What the tests read off the page: the image element's load marker ("REV WxH"),
# the status line, the diagnostics, the pixel readout, whether the image is stale.
PAGE_STATE = """(() => {
  const g = (id) => document.getElementById(id);
  if (!g('image'))  // still about:blank, or the page not yet parsed
    return JSON.stringify({loaded: '', stale: false, status: '', diagnostics: '', pixel: '',
                           stats: ''});
  return JSON.stringify({
    loaded: g('image').dataset.loaded || '',
    stale: g('image').classList.contains('stale'),
    status: g('status').textContent,
    diagnostics: g('diagnostics').textContent,
    pixel: g('pixel').textContent,
    stats: g('stats').textContent});
})()"""
