"""snell watch --display-server against a mock tev (ctest -L watch): a TCP server that
parses tev's IPC packets (length, type, payload; CreateImage 4, UpdateImage 3) and
rebuilds the image from the tiles. Checks the image's name, size and channels, that the
tiles cover it, that its pixels are the linear floats the page serves (/image.f32), that
an edit of the scene streams a new image, and that an edit cancels a long render at once.
Usage: test_tev.py SNELL"""

import os
import re
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from watch_process import SnellWatch, save_like_an_editor  # noqa: E402

SCENE = """settings {{ resolution <150, 20> samples 16 }}
camera {{ location <0, 0, -5> look_at <0, 0, 0> fov 40 }}
background {bg}
point_light {{ position <-3, 6, -4> intensity <60, 60, 60> }}
sphere {{ center <0, 0, 0> radius 1 material diffuse <0.8, 0.3, 0.2> }}
"""


class MockTev:
    def __init__(self):
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(1)
        self.port = self.sock.getsockname()[1]
        self.lock = threading.Lock()
        self.images = {}     # name -> {"size": (w, h), "channels": [...], "pixels": {...}}
        self.updates = 0     # UpdateImage packets, all images
        self.errors = []
        threading.Thread(target=self.serve, daemon=True).start()

    def serve(self):
        conn, _ = self.sock.accept()
        buf = b""
        while True:
            chunk = conn.recv(1 << 20)
            if not chunk:
                return
            buf += chunk
            while len(buf) >= 4:
                (length,) = struct.unpack_from("<I", buf)
                if length < 5:
                    self.errors.append(f"packet length {length}")
                    return
                if len(buf) < length:
                    break
                packet, buf = buf[:length], buf[length:]
                try:
                    self.parse(packet)
                except Exception as e:  # a malformed packet fails the test
                    self.errors.append(f"cannot parse a packet: {e!r}")

    @staticmethod
    def string(p, at):
        end = p.index(b"\0", at)
        return p[at:end].decode(), end + 1

    def parse(self, p):
        kind = p[4]
        at = 5
        if kind == 4:  # CreateImage: focus, name, width, height, nChannels, names
            at += 1
            name, at = self.string(p, at)
            w, h, n = struct.unpack_from("<iii", p, at)
            at += 12
            channels = []
            for _ in range(n):
                c, at = self.string(p, at)
                channels.append(c)
            if at != len(p):
                self.errors.append("CreateImage has trailing bytes")
            with self.lock:
                self.images[name] = {"size": (w, h), "channels": channels, "pixels": {}}
        elif kind == 3:  # UpdateImage: focus, name, channel, x, y, w, h, floats
            at += 1
            name, at = self.string(p, at)
            channel, at = self.string(p, at)
            x, y, w, h = struct.unpack_from("<iiii", p, at)
            at += 16
            if len(p) - at != 4 * w * h:
                self.errors.append(f"UpdateImage {w}x{h} carries {len(p) - at} bytes")
                return
            values = struct.unpack_from(f"<{w * h}f", p, at)
            with self.lock:
                img = self.images.get(name)
                if img is None:
                    self.errors.append(f"UpdateImage for {name!r} before its CreateImage")
                    return
                W, H = img["size"]
                if x < 0 or y < 0 or x + w > W or y + h > H:
                    self.errors.append(f"tile {x},{y} {w}x{h} outside {W}x{H}")
                    return
                for j in range(h):
                    for i in range(w):
                        img["pixels"][(channel, x + i, y + j)] = values[j * w + i]
                self.updates += 1
        else:
            self.errors.append(f"unexpected packet type {kind}")

    def pixel(self, name, x, y):
        with self.lock:
            px = self.images[name]["pixels"]
            return tuple(px.get((c, x, y)) for c in "RGB")


def wait(pred, what, timeout=30):
    end = time.time() + timeout
    while time.time() < end:
        if pred():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


def main():
    snell = sys.argv[1]
    folder = tempfile.mkdtemp(prefix="snell-tev-test-")
    scene = os.path.join(folder, "scene.scn")
    with open(scene, "w") as f:
        f.write(SCENE.format(bg="<0.25, 0.5, 0.75>"))
    tev = MockTev()
    watch = None
    try:
        watch = SnellWatch(snell, scene, "--display-server", f"127.0.0.1:{tev.port}")
        name = f"snell watch: {scene}"
        done = lambda s: s["status"].startswith("done")  # noqa: E731
        watch.wait_state(done, what="the last pass")
        W, H = 150, 20
        # The last pass's floats as the page serves them; tev must end with exactly these
        # (the stream keeps only the newest image, so a pass may be skipped, never the last).
        floats = struct.unpack(f"<{3 * W * H}f", watch.get("/image.f32"))

        def tev_matches():
            with tev.lock:
                img = tev.images.get(name)
                if not img or len(img["pixels"]) != 3 * W * H:
                    return False
            return all(tev.pixel(name, x, y) == floats[3 * (y * W + x): 3 * (y * W + x) + 3]
                       for y in range(H) for x in range(W))

        # Whole images only: 2 tiles (128 + 22 wide) x 3 channels each. (The right tile
        # is all background, the same in every pass: the pixels can match before its
        # packets of the last pass are in.)
        wait(lambda: tev_matches() and tev.updates % 6 == 0,
             "tev's image to equal the page's floats")
        time.sleep(0.2)
        assert not tev.errors, tev.errors
        assert tev.updates >= 6 and tev.updates % 6 == 0, tev.updates
        assert list(tev.images) == [name], list(tev.images)
        img = tev.images[name]
        assert img["size"] == (W, H), img["size"]
        assert img["channels"] == ["R", "G", "B"], img["channels"]
        # The corner sees the background; the centre the lit red sphere.
        corner = tev.pixel(name, 0, 0)
        assert all(abs(a - b) < 1e-6 for a, b in zip(corner, (0.25, 0.5, 0.75))), corner
        centre = tev.pixel(name, W // 2, H // 2)
        assert centre[0] > centre[1] > 0, centre

        # An edit: a new image, in place (same name and size, no new CreateImage).
        before = tev.updates
        save_like_an_editor(scene, SCENE.format(bg="<1, 0, 0.5>"))
        wait(lambda: tev.pixel(name, 0, 0) == (1.0, 0.0, 0.5), "the edited background in tev")
        assert tev.updates > before
        assert not tev.errors, tev.errors

        # A stale render is cancelled at once: a scene of 2^20 spp (minutes of passes)
        # is replaced while a long pass runs; the new scene's last pass comes in seconds.
        slow = SCENE.replace("samples 16", "samples 1048576")
        save_like_an_editor(scene, slow.format(bg="<0, 1, 0>"))
        def long_pass(s):
            m = re.match(r"rendering pass (\d+)/", s["status"])
            return m and int(m.group(1)) >= 5 and s["target_spp"] == 1 << 20

        watch.wait_state(long_pass, what="a long pass under way")
        t0 = time.time()
        save_like_an_editor(scene, SCENE.replace("samples 16", "samples 4").format(bg="<0, 0, 1>"))
        watch.wait_state(lambda s: s["status"].startswith("done") and s["target_spp"] == 4,
                         timeout=10, what="the new scene's last pass")
        cancel_seconds = time.time() - t0
        wait(lambda: tev.pixel(name, 0, 0) == (0.0, 0.0, 1.0), "the new scene in tev")
        assert not tev.errors, tev.errors
        print(f"a 2^20 spp render replaced: new scene done {cancel_seconds:.2f} s after the save")

        # A second watch on the same port is an error (exit 3), not a second server
        # sharing it (cpp-httplib's default SO_REUSEPORT would have let it bind).
        port = watch.url.rstrip("/").rsplit(":", 1)[1]
        second = subprocess.run([snell, "watch", scene, "--port", port, "-q"],
                                capture_output=True, text=True, timeout=20)
        assert second.returncode == 3, (second.returncode, second.stderr)
        assert "cannot listen on 127.0.0.1:" + port in second.stderr, second.stderr
        # Options no edit of the scene can fix end the watch with exit 2, as render's
        # do (it waited for a change instead).
        for bad in (["--res", "0x0"], ["--set", "foo=1"], ["--display-server", "127.0.0.1:99999"]):
            r = subprocess.run([snell, "watch", scene, "--port", "0", "-q", "--threads", "1", *bad],
                               capture_output=True, text=True, timeout=20)
            assert r.returncode == 2, (bad, r.returncode, r.stderr)
        print(f"tev stream: {tev.updates} UpdateImage packets, image {name!r} {W}x{H}")
    finally:
        if watch:
            code = watch.stop()
            assert code == 0, f"snell watch exited {code} on SIGTERM"
        for n in os.listdir(folder):
            os.unlink(os.path.join(folder, n))
        os.rmdir(folder)


if __name__ == "__main__":
    main()
