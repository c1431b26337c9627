#!/usr/bin/env python3
"""Requests per second against a running granulabd on one kept-alive connection and on a fresh connection
per request (standard library only). Usage: keepalive.py PORT"""
import http.client, time, sys
port = int(sys.argv[1])
c = http.client.HTTPConnection("127.0.0.1", port)
n = 200
t = time.time()
for _ in range(n):
    c.request("GET", "/v1/health"); r = c.getresponse(); r.read()
dt = time.time() - t
print(f"keep-alive: {n/dt:.0f} req/s ({1000*dt/n:.2f} ms/request)")
t = time.time()
for _ in range(n):
    c2 = http.client.HTTPConnection("127.0.0.1", port); c2.request("GET", "/v1/health"); c2.getresponse().read(); c2.close()
dt = time.time() - t
print(f"new connection each: {n/dt:.0f} req/s")
