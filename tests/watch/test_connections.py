"""The watch page keeps answering while other connections sit idle: 40 sockets that
connect and send nothing, and 10 that send half a request, do not delay a request
for /state past a second (they held cpp-httplib's 8 workers for 5 s each, so every
request waited for them). The idle sockets are then closed by the server within its
read timeout. Usage: test_connections.py SNELL"""

import os
import shutil
import socket
import sys
import tempfile
import time
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from watch_process import SnellWatch  # noqa: E402

SCENE = """settings { resolution <16, 16> samples 1 }
camera { location <0, 0, -5> look_at <0, 0, 0> fov 40 }
background <0.25, 0.5, 0.75>
"""


def main():
    snell = sys.argv[1]
    folder = tempfile.mkdtemp(prefix="snell-watch-conn-")
    scene = os.path.join(folder, "scene.scn")
    with open(scene, "w") as f:
        f.write(SCENE)
    watch = None
    idle = []
    try:
        watch = SnellWatch(snell, scene, "--quiet")
        watch.wait_state(lambda s: s.get("spp", 0) > 0, what="a first image")
        host, port = watch.url.split("//")[1].rstrip("/").split(":")
        for i in range(50):
            s = socket.create_connection((host, int(port)), timeout=5)
            if i >= 40:
                s.sendall(b"GET /state HTTP/1.1\r\nHost: x\r\n")  # no blank line
            idle.append(s)
        time.sleep(0.2)  # the server has accepted them all
        worst = 0.0
        for _ in range(5):
            t0 = time.time()
            with urllib.request.urlopen(watch.url.rstrip("/") + "/state", timeout=10) as r:
                assert r.status == 200
                r.read()
            worst = max(worst, time.time() - t0)
        assert worst < 1.0, f"/state took {worst:.2f} s beside 50 idle connections"
        # The server closes the idle ones itself (read timeout 2 s): recv sees EOF
        # (after whatever answer it gives a half request).
        closed = 0
        deadline = time.time() + 8
        for s in idle:
            try:
                while True:
                    s.settimeout(max(0.1, deadline - time.time()))
                    if s.recv(4096) == b"":
                        closed += 1
                        break
            except (socket.timeout, ConnectionResetError):
                pass
        assert closed == len(idle), f"{closed} of {len(idle)} idle connections closed"
        assert watch.proc.poll() is None, "snell watch ended"
        print(f"ok: /state in at most {worst * 1000:.0f} ms beside 50 idle connections")
    finally:
        for s in idle:
            s.close()
        if watch:
            watch.stop()
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
