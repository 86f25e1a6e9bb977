#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Simulation of tensor_query_client load balancing (issue 21, docs/BENCHMARKS.md): C clients
over S query servers, each server one worker taking requests first come first served, with
service times drawn from measured ones. Compares the client policies:

  none               every client on one server: the newest announcement (as upstream's and
                     our load-balance=none do), i.e. all clients on the same server
  none-spread        each client on one server picked at random (a static assignment by hand)
  round-robin        each client sends its requests to the servers in turn (random start)
  least-outstanding  each client sends to the server where *it* has the fewest requests in
                     flight (it cannot see the other clients' requests)

Clients send open-loop (Poisson) at a total rate of `load` x the servers' capacity, each with
at most `window` requests in flight (max-request; an input beyond it is dropped and counted).
Service times: --service FILE (one per line, ms: e.g. the tensor_filter latencies of a MobileNet
server) or a lognormal around --mean-ms; --slow K makes K servers --slow-factor times slower
(a mixed fleet). Reports throughput (answers/s), p50/p99 latency (send -> answer) and drops.

usage: query_lb_sim.py [--clients 100] [--servers 10] [--load 0.7] [--seconds 60] [--window 4]
                       [--mean-ms 20] [--service FILE] [--slow 2] [--slow-factor 2] [--seed 1]
"""
import argparse
import heapq
import math
import random


def percentile(v, q):
    if not v:
        return 0.0
    v = sorted(v)
    return v[min(len(v) - 1, int(q * len(v)))]


def simulate(policy, a, service):
    rng = random.Random(a.seed)
    speed = [a.slow_factor if s < a.slow else 1.0 for s in range(a.servers)]
    capacity = sum(1.0 / (statistics_mean(service) * f / 1000.0) for f in speed)
    rate = a.load * capacity / a.clients  # requests/s per client
    busy_until = [0.0] * a.servers
    inflight = [[0] * a.servers for _ in range(a.clients)]
    total_inflight = [0] * a.clients
    rr = [rng.randrange(a.servers) for _ in range(a.clients)]
    fixed = [rng.randrange(a.servers) for _ in range(a.clients)]
    newest = a.servers - 1
    events = []  # (time, kind, client, server, sent)
    for c in range(a.clients):
        heapq.heappush(events, (rng.expovariate(rate), 0, c, -1, 0.0))
    lat, dropped, done = [], 0, 0
    while events:
        t, kind, c, s, sent = heapq.heappop(events)
        if kind == 1:  # an answer
            inflight[c][s] -= 1
            total_inflight[c] -= 1
            if sent >= a.warmup:
                lat.append((t - sent) * 1000.0)
                done += 1
            continue
        if t < a.seconds:
            heapq.heappush(events, (t + rng.expovariate(rate), 0, c, -1, 0.0))
        else:
            continue
        if total_inflight[c] >= a.window:
            dropped += 1
            continue
        if policy == "none":
            s = newest
        elif policy == "none-spread":
            s = fixed[c]
        elif policy == "round-robin":
            s = rr[c]
            rr[c] = (rr[c] + 1) % a.servers
        else:  # least-outstanding, ties in turn
            best = None
            for k in range(a.servers):
                i = (rr[c] + k) % a.servers
                if best is None or inflight[c][i] < inflight[c][best]:
                    best = i
            s = best
            rr[c] = (rr[c] + 1) % a.servers
        st = rng.choice(service) * speed[s] / 1000.0
        start = max(t, busy_until[s])
        busy_until[s] = start + st
        inflight[c][s] += 1
        total_inflight[c] += 1
        heapq.heappush(events, (start + st, 1, c, s, t))
    span = a.seconds - a.warmup
    return done / span, percentile(lat, 0.5), percentile(lat, 0.99), dropped, capacity


def statistics_mean(v):
    return sum(v) / len(v)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--clients", type=int, default=100)
    p.add_argument("--servers", type=int, default=10)
    p.add_argument("--load", type=float, default=0.7)
    p.add_argument("--seconds", type=float, default=60.0)
    p.add_argument("--warmup", type=float, default=5.0)
    p.add_argument("--window", type=int, default=4)
    p.add_argument("--mean-ms", type=float, default=20.0)
    p.add_argument("--service", help="measured service times, ms, one per line")
    p.add_argument("--slow", type=int, default=2)
    p.add_argument("--slow-factor", type=float, default=2.0)
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    rng = random.Random(a.seed + 1000)
    if a.service:
        with open(a.service) as f:
            service = [float(x) for x in f.read().split() if x.strip()]
        src = "%d measured service times from %s" % (len(service), a.service)
    else:
        sigma = 0.3
        mu = math.log(a.mean_ms) - sigma * sigma / 2
        service = [rng.lognormvariate(mu, sigma) for _ in range(10000)]
        src = "lognormal service times, mean %.1f ms, sigma %.2f" % (a.mean_ms, sigma)
    print("%d clients, %d servers (%d of them %.1fx slower), load %.2f of capacity, window %d, "
          "%s, %.0f s simulated" % (a.clients, a.servers, a.slow, a.slow_factor, a.load, a.window,
                                    src, a.seconds))
    print("%-18s %12s %10s %10s %9s" % ("policy", "answers/s", "p50 ms", "p99 ms", "dropped"))
    for policy in ("none", "none-spread", "round-robin", "least-outstanding"):
        fps, p50, p99, dropped, cap = simulate(policy, a, service)
        print("%-18s %12.1f %10.1f %10.1f %9d" % (policy, fps, p50, p99, dropped))
    print("capacity (all servers busy): %.1f answers/s" % cap)


if __name__ == "__main__":
    main()
