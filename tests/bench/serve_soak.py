#!/usr/bin/env python3
"""The service under everything at once, for a bounded time (issue 30's soak test; a benchmark,
not part of CI): 4 sessions orbiting the scene, 2 path jobs with video, a study, 20 slow clients
sending their headers a byte a second, and bursts of 100 renders at once, each client from an
address of its own (127.0.0.x; the per-address cap is the server's default). Then a quiet spell.

  tests/bench/serve_soak.py HLODR DATA_FOLDER [--seconds 300] [--quiet-seconds 30]

Prints p50/p99 latency of /healthz and of frames (session frames and burst renders), the
answers by kind (none may be a connection reset or a 5xx other than 503 busy / Retry-After),
and the server's resident memory at start, at its peak and at the end, sampled every 0.5 s.
The whole run stays under 10 minutes (the load is capped at 500 s).
"""
import argparse
import http.client
import json
import math
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import shutil


class Stats:
    def __init__(self):
        self.lock = threading.Lock()
        self.latency = {}   # what -> [ms]
        self.answers = {}   # kind -> count

    def add(self, what, ms=None, kind=None):
        with self.lock:
            if ms is not None:
                self.latency.setdefault(what, []).append(ms)
            if kind is not None:
                self.answers[kind] = self.answers.get(kind, 0) + 1


def call(port, source, method, path, body=None, timeout=120):
    """(status, headers, body) or raises; the client binds to its own loopback address."""
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout,
                                   source_address=(source, 0))
    try:
        headers = {"Content-Type": "application/json"} if body is not None else {}
        c.request(method, path, body=None if body is None else json.dumps(body), headers=headers)
        r = c.getresponse()
        return r.status, dict(r.getheaders()), r.read()
    finally:
        c.close()


def kind_of(status, body):
    if status < 500 or status == 503:
        try:
            code = json.loads(body)["error"]["code"]
        except Exception:
            code = ""
        return f"{status}" + (f" {code}" if code else "")
    return f"{status} (5xx)"


def timed(stats, what, port, source, method, path, body=None):
    t0 = time.time()
    try:
        s, h, b = call(port, source, method, path, body)
    except (ConnectionResetError, BrokenPipeError):
        stats.add(what, kind="connection reset")
        return None
    except socket.timeout:
        stats.add(what, kind="timeout")
        return None
    except OSError as e:
        stats.add(what, kind=type(e).__name__)
        return None
    ms = (time.time() - t0) * 1000
    if s == 200:
        stats.add(what, ms=ms, kind=f"{what} 200")
    else:
        stats.add(what, kind=f"{what} {kind_of(s, b)}")
    return s, h, b


def rss_kb(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def pct(values, q):
    if not values:
        return float("nan")
    v = sorted(values)
    return v[min(len(v) - 1, int(math.ceil(q * len(v))) - 1)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary")
    ap.add_argument("data")
    ap.add_argument("--seconds", type=float, default=300)
    ap.add_argument("--quiet-seconds", type=float, default=30)
    ap.add_argument("--port", type=int, default=30000 + os.getpid() % 2000)
    a = ap.parse_args()
    load_seconds = min(a.seconds, 500)
    port = a.port
    scene = sorted(n[:-5] for n in os.listdir(a.data) if n.endswith(".hlod"))[0]
    jobs = tempfile.mkdtemp(prefix="hlodr_soak_jobs_")
    server_log = open(os.path.join(jobs, "server.log"), "wb")
    server = subprocess.Popen([a.binary, "serve", "--data", a.data, "--jobs-dir", jobs,
                               "--port", str(port), "--quiet"],
                              stdout=server_log, stderr=subprocess.STDOUT)
    print(f"server log: {server_log.name}", flush=True)
    for _ in range(600):
        try:
            if call(port, "127.0.0.1", "GET", "/healthz", timeout=2)[0] == 200:
                break
        except OSError:
            time.sleep(0.1)
    info = json.loads(call(port, "127.0.0.1", "GET", "/api/scenes")[2])["scenes"][0]
    cam = info["defaultCamera"]
    target = cam["target"]
    radius = math.dist(cam["position"][:2], target[:2])
    height = cam["position"][2]

    stats = Stats()
    stop = threading.Event()
    rss = {"start": rss_kb(server.pid), "peak": 0, "samples": []}

    def sample_rss():
        while not stop.is_set() or rss.get("quiet") is None:
            r = rss_kb(server.pid)
            rss["peak"] = max(rss["peak"], r)
            rss["samples"].append((time.time(), r))
            time.sleep(0.5)
            if rss.get("quiet") is not None and time.time() > rss["quiet"]:
                return

    def healthz():
        while not stop.is_set():
            timed(stats, "healthz", port, "127.0.0.1", "GET", "/healthz")
            time.sleep(0.1)

    def orbiter(k):
        source = f"127.0.0.{2 + k}"
        r = timed(stats, "session create", port, source, "POST", "/api/sessions",
                  {"scene": scene, "width": 640, "height": 360})
        if not r or r[0] != 201:
            return
        sid = json.loads(r[2])["id"]
        i = 0
        while not stop.is_set():
            a_ = 2 * math.pi * (i / 120.0 + k / 4.0)
            camera = {"position": [target[0] + radius * math.cos(a_),
                                   target[1] + radius * math.sin(a_), height],
                      "target": target}
            timed(stats, "session frame", port, source, "POST", f"/api/sessions/{sid}/frame",
                  {"camera": camera, "still": i % 30 == 29})
            i += 1
        call(port, source, "DELETE", f"/api/sessions/{sid}")

    def jobs_loop(k):
        source = f"127.0.0.{10 + k}"
        while not stop.is_set():
            r = timed(stats, "job submit", port, source, "POST", "/api/jobs",
                      {"scene": scene, "path": {"kind": "orbit"}, "fps": 30, "frames": 900,
                       "video": True, "width": 640, "height": 360})
            if not r or r[0] != 202:
                time.sleep(1)
                continue
            jid = json.loads(r[2])["id"]
            while not stop.is_set():
                s = call(port, source, "GET", f"/api/jobs/{jid}")
                if json.loads(s[2]).get("finished"):
                    break
                time.sleep(1)
            call(port, source, "DELETE", f"/api/jobs/{jid}")

    def study_loop():
        source = "127.0.0.20"
        while not stop.is_set():
            r = timed(stats, "study submit", port, source, "POST", "/api/studies",
                      {"scene": scene, "path": {"kind": "orbit"}, "frames": 4,
                       "budgets": [16, 33], "selectors": ["lakhia", "sse"], "ssePx": [8],
                       "width": 320, "height": 180, "strips": 1})
            if not r or r[0] != 202:
                time.sleep(1)
                continue
            aid = json.loads(r[2])["id"]
            while not stop.is_set():
                if json.loads(call(port, source, "GET", f"/api/studies/{aid}")[2]).get("finished"):
                    break
                time.sleep(1)
            call(port, source, "DELETE", f"/api/studies/{aid}")

    def slow_client(k):
        head = b"GET /api/scenes HTTP/1.1\r\nHost: slow\r\nX-Pad: " + b"s" * 64 + b"\r\n\r\n"
        while not stop.is_set():
            try:
                s = socket.create_connection(("127.0.0.1", port),
                                             source_address=(f"127.0.0.{30 + k}", 0))
                s.settimeout(1.0)
                for i in range(len(head)):
                    if stop.is_set():
                        break
                    s.send(head[i:i + 1])
                    try:
                        if s.recv(64):
                            stats.add("slow", kind="slow client answered (408)")
                            break
                    except socket.timeout:
                        pass
                s.close()
            except OSError as e:
                stats.add("slow", kind=f"slow client {type(e).__name__}")
                time.sleep(1)

    def bursts():
        n = 0
        while not stop.wait(10 if n else 5):
            n += 1
            threads = [threading.Thread(
                target=timed, args=(stats, "burst render", port, f"127.0.1.{1 + i}", "POST",
                                    "/api/render", {"scene": scene, "width": 320, "height": 180}))
                for i in range(100)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
        stats.add("bursts", kind=f"bursts of 100: {n}")

    sampler = threading.Thread(target=sample_rss)
    sampler.start()
    workers = [threading.Thread(target=healthz)]
    workers += [threading.Thread(target=orbiter, args=(k,)) for k in range(4)]
    workers += [threading.Thread(target=jobs_loop, args=(k,)) for k in range(2)]
    workers += [threading.Thread(target=study_loop)]
    workers += [threading.Thread(target=slow_client, args=(k,)) for k in range(20)]
    workers += [threading.Thread(target=bursts)]
    t0 = time.time()
    for w in workers:
        w.start()
    time.sleep(load_seconds)
    stop.set()
    for w in workers:
        w.join(timeout=120)
    load_end = time.time()
    rss["at_load_end"] = rss_kb(server.pid)
    rss["quiet"] = time.time() + a.quiet_seconds
    sampler.join()
    rss["end"] = rss_kb(server.pid)
    server.send_signal(signal.SIGTERM)
    server.wait(timeout=60)
    shutil.rmtree(jobs, ignore_errors=True)

    print(f"soak: {load_seconds:.0f} s of load, then {a.quiet_seconds:.0f} s quiet; "
          f"{os.cpu_count()} cores; load average {os.getloadavg()[0]:.1f}")
    for what in ["healthz", "session frame", "burst render"]:
        v = stats.latency.get(what, [])
        print(f"  {what:14s} n={len(v):6d}  p50 {pct(v, 0.5):8.1f} ms  p99 {pct(v, 0.99):8.1f} ms")
    print("  answers by kind:")
    bad = 0
    for k in sorted(stats.answers):
        print(f"    {stats.answers[k]:7d}  {k}")
        if "reset" in k or "(5xx)" in k or "Error" in k:
            bad += stats.answers[k]
    print(f"  resident memory: start {rss['start'] / 1024:.0f} MB, peak {rss['peak'] / 1024:.0f} MB, "
          f"at the end of the load {rss['at_load_end'] / 1024:.0f} MB, "
          f"after {a.quiet_seconds:.0f} s quiet {rss['end'] / 1024:.0f} MB")
    print(f"  resets, 5xx (not 503) and connection errors: {bad}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
