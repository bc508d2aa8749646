#!/usr/bin/env python3
"""Drags sent to the editor's server one after the other, without a browser.

Starts `laplacian_deform --serve` on a free port, opens a session on a mesh of the data folder,
then, for each selection (a handle vertex and its ROI grown by --grow rings around it), sends
--drags drags of --iterations iterations each, one after the other (each waits for the previous
reply, as the editor does), and prints the server's own times per drag: the whole update, its
local step and its solve (ms). A drag is counted as slow when its local step takes more than 1.4
times the fastest of its selection (the first drag of each selection is left out: it starts
from the rest pose). Such drags come in streaks when another thread takes a core from the
deformer's threads (see the user manual, Performance, 2026-12-08). Prints numbers; asserts
nothing (timings depend on the machine and its load).

   usage: python3 benchmark/server_drags.py --server PATH/laplacian_deform
              [--mesh armadillo.off] [--runs 3] [--drags 10] [--iterations 4] [--grow 22]
              [--handles 13000,13000,1000,13000]
"""
import argparse
import http.client
import json
import re
import shutil
import subprocess
import sys
import tempfile


def run_once(args):
    out = tempfile.mkdtemp(prefix='server-drags-')
    server = subprocess.Popen([args.server, '--serve', '--port', '0', '--output', out],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        url = None
        for line in server.stdout:
            m = re.search(r'editor at (http://127\.0\.0\.1:(\d+)/\S*)', line)
            if m:
                url, port = m.group(1), int(m.group(2))
                break
        if url is None:
            sys.exit('the server did not start')
        token = re.search(r'token=([0-9a-f]+)', url).group(1)
        connection = http.client.HTTPConnection('127.0.0.1', port)

        def post(path, body):
            connection.request('POST', path, json.dumps(body),
                               {'Content-Type': 'application/json', 'X-Editor-Token': token})
            reply = connection.getresponse()
            data = json.loads(reply.read())
            if reply.status != 200:
                sys.exit(f'{path}: {reply.status} {data}')
            return data

        session = post('/api/session', {'mesh': args.mesh})['session']
        slow = counted = 0
        for handle in args.handles:
            r = post('/api/select', {'session': session, 'roi': [], 'handles': [handle], 'grow': args.grow})
            times = []
            for i in range(args.drags):
                d = post('/api/drag', {'session': session, 'translation': [0.001 * i, 0.002 * i, 0],
                                       'iterations': args.iterations})
                times.append((d['seconds'] * 1e3, d['local_step_seconds'] * 1e3, d['solve_seconds'] * 1e3))
            local = [t[1] for t in times[1:]]
            fastest = min(local)
            s = sum(1 for x in local if x > 1.4 * fastest)
            slow += s
            counted += len(local)
            print(f'selection around {handle}: ROI {len(r["roi"])}, preprocess {r["preprocess_seconds"] * 1e3:.1f} ms; '
                  f'drags (update/local/solve ms): ' + ' '.join('%.1f/%.1f/%.1f' % t for t in times) +
                  f'; slow {s} of {len(local)}')
        return slow, counted
    finally:
        server.kill()
        server.wait()
        shutil.rmtree(out, ignore_errors=True)   # the server writes there only on /api/save


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('--server', required=True)
    p.add_argument('--mesh', default='armadillo.off')
    p.add_argument('--runs', type=int, default=3)
    p.add_argument('--drags', type=int, default=10)
    p.add_argument('--iterations', type=int, default=4)
    p.add_argument('--grow', type=int, default=22)
    p.add_argument('--handles', default='13000,13000,1000,13000')
    args = p.parse_args()
    args.handles = [int(h) for h in args.handles.split(',')]
    if args.drags < 2:
        sys.exit('--drags must be at least 2')
    slow = counted = 0
    for _ in range(args.runs):
        s, c = run_once(args)
        slow += s
        counted += c
    print(f'slow drags (local step > 1.4 x the fastest of their selection): {slow} of {counted}')


if __name__ == '__main__':
    main()
