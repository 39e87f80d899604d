#!/usr/bin/env python3
"""The hostile points of issue 30 against a running `hlodr serve`, one line each: PASS or FAIL
with what was seen. Not part of CI (the service tests assert the same in-process); this runs
the points against any hlodr binary, so that one built before a fix shows what it fixed.

  tests/bench/serve_hostile.py HLODR DATA_FOLDER [--port N]

DATA_FOLDER holds NAME.hlod stores (the first is used); the jobs go to a temporary folder.
"""
import argparse
import http.client
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time


def request(port, method, path, body=None, headers=None, timeout=60):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    try:
        c.request(method, path, body=body, headers=headers or {})
        r = c.getresponse()
        return r.status, dict(r.getheaders()), r.read()
    finally:
        c.close()


def post_json(port, path, obj, content_type="application/json"):
    return request(port, "POST", path, json.dumps(obj), {"Content-Type": content_type})


class Server:
    def __init__(self, binary, data, jobs, port, extra=()):
        self.args = [binary, "serve", "--data", data, "--jobs-dir", jobs, "--port", str(port),
                     "--quiet", *extra]
        self.port = port
        self.proc = None

    def start(self):
        self.proc = subprocess.Popen(self.args, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        for _ in range(300):
            try:
                if request(self.port, "GET", "/healthz", timeout=2)[0] == 200:
                    return
            except OSError:
                pass
            time.sleep(0.1)
        raise RuntimeError("the server did not start")

    def stop(self):
        self.proc.send_signal(signal.SIGTERM)
        self.proc.wait(timeout=60)


def wait_job(port, jid, collection="jobs"):
    for _ in range(1200):
        s, _, b = request(port, "GET", f"/api/{collection}/{jid}")
        j = json.loads(b)
        if j.get("finished"):
            return j
        time.sleep(0.1)
    return {}


def check_slow_clients(port):
    conns = []
    for _ in range(60):
        s = socket.create_connection(("127.0.0.1", port))
        conns.append(s)
    head = b"GET /api/scenes HTTP/1.1\r\nHost: slow\r\nX-Pad: " + b"x" * 200 + b"\r\n\r\n"
    stop = threading.Event()

    def trickle():
        for i in range(len(head) - 4):
            if stop.is_set():
                return
            for s in conns:
                try:
                    s.send(head[i:i + 1])
                except OSError:
                    pass
            time.sleep(0.1)

    t = threading.Thread(target=trickle)
    t.start()
    time.sleep(0.3)
    ms, failed = [], 0
    end = time.time() + 3
    while time.time() < end:
        t0 = time.time()
        try:
            if request(port, "GET", "/healthz", timeout=5)[0] != 200:
                failed += 1
        except OSError:
            failed += 1
        ms.append((time.time() - t0) * 1000)
        time.sleep(0.05)
    stop.set()
    t.join()
    for s in conns:
        s.close()
    ms.sort()
    p90 = ms[int(len(ms) * 0.9)]
    ok = failed == 0 and p90 <= 100
    return ok, f"/healthz with 60 slow clients: {len(ms)} probes, {failed} failed, " \
               f"median {ms[len(ms) // 2]:.1f} ms, p90 {p90:.1f} ms, max {ms[-1]:.1f} ms"


def check_header_deadline(port):
    s = socket.create_connection(("127.0.0.1", port))
    s.settimeout(0.1)
    head = b"GET /healthz HTTP/1.1\r\nX-Slow: " + b"y" * 400
    got = b""
    t0 = time.time()
    closed = False
    for i in range(len(head)):
        if time.time() - t0 > 14:
            break
        try:
            s.send(head[i:i + 1])
        except OSError:
            closed = True
            break
        try:
            chunk = s.recv(4096)
            if not chunk:
                closed = True
                break
            got += chunk
        except socket.timeout:
            pass
        except OSError:
            closed = True
            break
    s.close()
    ok = closed and got.startswith(b"HTTP/1.1 408")
    return ok, f"a head trickling a byte per 100 ms: closed={closed} after {time.time() - t0:.1f} s, " \
               f"answer {got[:12]!r}"


def check_per_address(port):
    conns = [socket.create_connection(("127.0.0.1", port)) for _ in range(70)]
    time.sleep(0.3)
    try:
        s, h, b = request(port, "GET", "/api/scenes", timeout=10)
        hz = request(port, "GET", "/healthz", timeout=10)[0]
    except OSError as e:
        s, h, b, hz = str(e), {}, b"", "-"
    for c in conns:
        c.close()
    ok = s == 503 and hz == 200
    return ok, f"70 idle connections from one address, then /api/scenes: {s}, /healthz: {hz}"


def check_bursts(port, scene):
    body = json.dumps({"scene": scene, "width": 32, "height": 32})
    lines, ok = [], True
    for burst in range(3):
        counts = {}
        lock = threading.Lock()
        go = threading.Event()

        def one():
            go.wait()
            try:
                k = request(port, "POST", "/api/render", body,
                            {"Content-Type": "application/json"}, timeout=120)[0]
            except OSError as e:
                k = type(e).__name__
            with lock:
                counts[k] = counts.get(k, 0) + 1

        ts = [threading.Thread(target=one) for _ in range(200)]
        for t in ts:
            t.start()
        go.set()
        for t in ts:
            t.join()
        ok = ok and set(counts) <= {200, 503}
        lines.append(str(dict(sorted(counts.items(), key=str))))
    return ok, "3 bursts of 200 renders: " + "; ".join(lines)


def check_utf8_id(port):
    s, _, b = request(port, "GET", "/api/jobs/%ff%fe")
    return s in (400, 404), f"GET /api/jobs/%ff%fe: {s} {b[:90]!r}"


def check_nul(port):
    s, h, b = request(port, "GET", "/index.html%00.js")
    ok = not (s == 200 and b"<" in b)
    return ok, f"GET /index.html%00.js: {s} {h.get('Content-Type', '')}"


def check_media_types(port, scene):
    body = {"scene": scene, "width": 32, "height": 32}
    upper = post_json(port, "/api/render", body, "APPLICATION/JSON")[0]
    x = post_json(port, "/api/render", body, "application/jsonx")[0]
    return upper == 200 and x == 415, f"APPLICATION/JSON: {upper}, application/jsonx: {x}"


def check_retry_after(port, scene):
    ids = []
    status, headers = None, {}
    for _ in range(3):  # --max-jobs 2
        s, h, b = post_json(port, "/api/jobs", {"scene": scene, "path": {"kind": "orbit"},
                                                 "frames": 3000, "width": 64, "height": 48})
        if s == 202:
            ids.append(json.loads(b)["id"])
        else:
            status, headers = s, h
    for jid in ids:
        request(port, "DELETE", f"/api/jobs/{jid}")
    for jid in ids:
        wait_job(port, jid)
    ok = status == 429 and "Retry-After" in headers
    return ok, f"a job past --max-jobs: {status}, Retry-After: {headers.get('Retry-After')}"


def check_cancelled_video(port, scene):
    s, _, b = post_json(port, "/api/jobs", {"scene": scene, "path": {"kind": "orbit"},
                                             "frames": 3000, "video": True, "width": 64,
                                             "height": 48})
    jid = json.loads(b)["id"]
    for _ in range(600):
        if json.loads(request(port, "GET", f"/api/jobs/{jid}")[2]).get("framesDone", 0) > 3:
            break
        time.sleep(0.05)
    request(port, "DELETE", f"/api/jobs/{jid}")
    j = wait_job(port, jid)
    s, _, b = request(port, "GET", f"/api/jobs/{jid}/video.mp4")
    return s == 200 and b"ftyp" in b, f"the video of a {j.get('state')} job: {s}"


def check_long_path(port, scene):
    path = {"keyframes": [
        {"time": 0, "position": [0, -100, 50], "target": [50, 50, 0]},
        {"time": 1e9, "position": [100, -100, 50], "target": [50, 50, 0]}]}
    s, _, b = post_json(port, "/api/jobs", {"scene": scene, "path": path, "frames": 1,
                                             "width": 64, "height": 48})
    if s == 202:
        wait_job(port, json.loads(b)["id"])
    return s == 202, f"a 1e9 s keyframe path with frames 1: {s} {b[:80]!r}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary")
    ap.add_argument("data")
    ap.add_argument("--port", type=int, default=28000 + os.getpid() % 2000)
    a = ap.parse_args()
    scene = sorted(n[:-5] for n in os.listdir(a.data) if n.endswith(".hlod"))[0]
    jobs = tempfile.mkdtemp(prefix="hlodr_hostile_jobs_")
    web = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "web")
    server = Server(a.binary, a.data, jobs, a.port, ["--max-jobs", "2", "--web", web])
    server.start()
    results = []
    try:
        for name, fn in [("slow clients", lambda: check_slow_clients(a.port)),
                         ("head deadline", lambda: check_header_deadline(a.port)),
                         ("per address", lambda: check_per_address(a.port)),
                         ("bursts", lambda: check_bursts(a.port, scene)),
                         ("utf-8 id", lambda: check_utf8_id(a.port)),
                         ("nul path", lambda: check_nul(a.port)),
                         ("media type", lambda: check_media_types(a.port, scene)),
                         ("429 retry", lambda: check_retry_after(a.port, scene)),
                         ("cancelled mp4", lambda: check_cancelled_video(a.port, scene)),
                         ("long path", lambda: check_long_path(a.port, scene))]:
            try:
                ok, what = fn()
            except Exception as e:  # a crash of the check is a failure of the point
                ok, what = False, f"{type(e).__name__}: {e}"
            results.append((name, ok, what))
            print(f"{'PASS' if ok else 'FAIL'}  {name:14s} {what}", flush=True)
        # Restart: the jobs above are listed again.
        before = json.loads(request(a.port, "GET", "/api/jobs")[2])["jobs"]
        server.stop()
        server.start()
        after = json.loads(request(a.port, "GET", "/api/jobs")[2])["jobs"]
        ok = len(before) > 0 and len(after) == len(before)
        print(f"{'PASS' if ok else 'FAIL'}  {'restart':14s} jobs before {len(before)}, "
              f"after a restart {len(after)}", flush=True)
        results.append(("restart", ok, ""))
    finally:
        server.stop()
        shutil.rmtree(jobs, ignore_errors=True)
    failed = [n for n, ok, _ in results if not ok]
    print(f"{len(results) - len(failed)} of {len(results)} passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
