#!/usr/bin/python3
"""The generalisation protocol of the default pipeline (docs/priors.md).

Runs `nrsfm.reconstruct(W, K)` with default options (what `nrsfm reconstruct
--input X --K N` runs) on the real sequences of ../shared/datasets and on data
made from them, and scores each result by the field's protocol: object-frame
e3D against the world-frame S for the Akhter et al. sequences (drink, pickup,
yoga), camera-frame e3D for face and frgc. Beside every object-frame e3D, the
rank-K floor: the e3D of the best rank-K approximation of the true shapes
(truncated SVD of the F x 3P matrix of centred true shapes), which no rank-K
answer can go below.

Parts (--parts, comma list; default all):
  ksweep   K = 2 ... published + 2 of drink, pickup, yoga
  subsets  random point subsets (P = 15, 25, 33), every 2nd and 3rd frame,
           a random half of the frames (seeded), K = 4 and 8 (4 for P = 15)
  orbits   the truth re-projected under 60/90/120 degree orbits, a ramp,
           1 % and 3 % noise (nrsfm synth --dataset reproject), published K
  units    W and S x 1000 and x 0.001: the same e3D to three digits
  frgc     400 faces, K = 3, 5, 8 (camera frame; rigid K = 1 for reference)
  face     the published K = 7 and K = 4

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/generalise.py
           [--shared ../shared] [--parts ksweep,frgc] [--threads 2]
           [--json generalise.json] [--set name=value ...]
--set passes a keyword of nrsfm.reconstruct to every run (a number, or a
string), to compare an option with its default on the same data.
Prints one line per run (as it goes) and a summary per part; --json writes
every row. Needs numpy and the nrsfm module (build/python).
"""
import argparse
import json
import os
import sys
import tempfile
import time
import zlib
import struct

import numpy as np
import nrsfm

PUBLISHED_K = {'drink': 12, 'pickup': 12, 'yoga': 10, 'face': 7}


# --- MATLAB v5 reading of the truth (numeric arrays only; numpy has no reader)
_TYPES = {1: np.int8, 2: np.uint8, 3: np.int16, 4: np.uint16, 5: np.int32,
          6: np.uint32, 7: np.float32, 9: np.float64, 12: np.int64, 13: np.uint64}


def _element(buffer, offset):
    kind, size = struct.unpack_from('<II', buffer, offset)
    if kind >> 16:  # small element: 4-byte tag
        return kind & 0xffff, buffer[offset + 4: offset + 4 + (kind >> 16)], offset + 8
    data = buffer[offset + 8: offset + 8 + size]
    padding = 0 if kind == 15 else (8 - size % 8) % 8
    return kind, data, offset + 8 + size + padding


def read_mat5(path):
    """{name: float64 array} of the numeric variables of a MATLAB v5 file."""
    buffer = open(path, 'rb').read()
    offset, out = 128, {}
    while offset + 8 <= len(buffer):
        kind, data, offset = _element(buffer, offset)
        if kind == 15:
            kind, data, _ = _element(zlib.decompress(data), 0)
        if kind != 14:
            continue
        at = 0
        _, _, at = _element(data, at)  # array flags
        _, dims, at = _element(data, at)
        _, name, at = _element(data, at)
        kind, real, at = _element(data, at)
        if kind in _TYPES:
            dims = tuple(np.frombuffer(dims, np.int32))
            out[name.decode()] = np.frombuffer(real, _TYPES[kind]).astype(float).reshape(
                dims, order='F')
    return out


# --- the metric (core/eval/metrics.h, ComputeE3D), for truths made here
def e3d(truth, estimate):
    """e3D of Akhter et al.: F x 3 x P arrays, one global alignment."""
    x = truth - truth.mean(axis=2, keepdims=True)
    y = estimate - estimate.mean(axis=2, keepdims=True)
    frames = x.shape[0]
    s = np.mean(np.std(x.reshape(3 * frames, -1), axis=1))
    c = np.einsum('fip,fjp->ij', x, y)
    m = np.einsum('fip,fjp->ij', y, y)
    u, _, vt = np.linalg.svd(c @ np.linalg.pinv(m))
    return float(np.mean(np.linalg.norm(x - np.einsum('ij,fjp->fip', u @ vt, y), axis=1)) / s)


def rank_floor(shapes, k):
    """e3D of the best rank-k approximation of the centred shapes."""
    x = shapes - shapes.mean(axis=2, keepdims=True)
    frames = x.shape[0]
    u, s, vt = np.linalg.svd(x.reshape(frames, -1), full_matrices=False)
    return e3d(shapes, ((u[:, :k] * s[:k]) @ vt[:k]).reshape(x.shape))


def akhter(path):
    """W (2F x P), world S (F x 3 x P) of an Akhter et al. file."""
    variables = read_mat5(path)
    s = variables['S']
    return variables['W'], s.reshape(s.shape[0] // 3, 3, -1)


ROWS = []
OPTIONS = {}  # --set: extra keywords of every nrsfm.reconstruct call


def run(part, name, k, w, mask, truth=None, truth_path=None, threads=2, **extra):
    """One default reconstruction, scored; prints and records the row."""
    start = time.time()
    try:
        r = nrsfm.reconstruct(w, k, mask=mask, threads=threads, **OPTIONS)
    except ValueError as error:
        print('%-9s %-28s K %2d  FAILED: %s' % (part, name, k, error), flush=True)
        ROWS.append(dict(part=part, name=name, K=k, error=str(error)))
        return None
    seconds = time.time() - start
    summary = r.summary
    diagnostics = summary['diagnostics']
    row = dict(part=part, name=name, K=k, seconds=round(seconds, 2),
               camera_K=int(diagnostics['camera_num_bases']),
               converged=bool(diagnostics['refine_converged'] == 1.0 and
                              diagnostics['camera_refine_converged'] != 0.0),
               iterations=sum(st['iterations'] for st in summary['stages']),
               terms=summary['term_weights'], **extra)
    if truth is not None:  # object frame vs world S
        row['e3d'] = e3d(truth, r.points_object)
        row['floor'] = rank_floor(truth, k)
        row['ratio'] = row['e3d'] / row['floor']
        row['frame'] = 'object'
    else:
        metrics = nrsfm.evaluate(truth_path, r)
        row['e3d'] = metrics['e3d']
        row['frame'] = metrics['e3d_frame']
    ROWS.append(row)
    ratio = '  ratio %5.2f (floor %.4f)' % (row['ratio'], row['floor']) if 'ratio' in row else ''
    print('%-9s %-28s K %2d  e3D %.4f %-6s%s  camera K %2d  %4d it  %s  %6.1f s' % (
        part, name, k, row['e3d'], row['frame'], ratio, row['camera_K'], row['iterations'],
        'tolerance' if row['converged'] else 'LIMIT', seconds), flush=True)
    return row


def ksweep(shared, threads):
    for name in ('drink', 'pickup', 'yoga'):
        w, s = akhter(os.path.join(shared, 'datasets', name + '.mat'))
        for k in range(2, PUBLISHED_K[name] + 3):
            run('ksweep', name, k, w, None, truth=s, threads=threads)


def subsets(shared, threads):
    rng = np.random.default_rng(2026)
    for name in ('drink', 'pickup', 'yoga'):
        w, s = akhter(os.path.join(shared, 'datasets', name + '.mat'))
        frames = s.shape[0]
        for points in (15, 25, 33):
            keep = np.sort(rng.choice(s.shape[2], points, replace=False))
            for k in ((4,) if points == 15 else (4, 8)):
                run('subsets', '%s P=%d' % (name, points), k, w[:, keep], None,
                    truth=s[:, :, keep], threads=threads)
        half = np.sort(rng.choice(frames, frames // 2, replace=False))
        for label, kept in (('every 2nd frame', np.arange(0, frames, 2)),
                            ('every 3rd frame', np.arange(0, frames, 3)),
                            ('random half of frames', half)):
            rows = np.stack([2 * kept, 2 * kept + 1], axis=1).reshape(-1)
            for k in (4, 8):
                run('subsets', '%s %s' % (name, label), k, w[rows], None, truth=s[kept],
                    threads=threads)


def orbits(shared, threads):
    cases = [('60 deg orbit', dict(rotation=60.0)), ('90 deg orbit', dict(rotation=90.0)),
             ('120 deg orbit', dict(rotation=120.0)),
             ('90 deg ramp', dict(rotation=90.0, profile='ramp')),
             ('120 deg, 1 % noise', dict(rotation=120.0, noise_fraction=0.01)),
             ('120 deg, 3 % noise', dict(rotation=120.0, noise_fraction=0.03))]
    with tempfile.TemporaryDirectory() as folder:
        for name in ('drink', 'pickup', 'yoga', 'face'):
            source = os.path.join(shared, 'datasets', name + '.mat')
            for label, options in cases:
                path = os.path.join(folder, 'orbit.mat')
                data = nrsfm.synth(dataset='reproject', input=source, output=path, seed=1,
                                   **options)
                run('orbits', '%s %s' % (name, label), PUBLISHED_K[name], data.W, data.mask,
                    truth_path=path, threads=threads)


def units(shared, threads):
    for name in ('pickup', 'yoga'):
        w, s = akhter(os.path.join(shared, 'datasets', name + '.mat'))
        for k in (4, 8):
            for factor in (1.0, 1000.0, 0.001):
                run('units', '%s x %g' % (name, factor), k, w * factor, None,
                    truth=s * factor, threads=threads, factor=factor)


def frgc(shared, threads):
    path = os.path.join(shared, 'datasets', 'frgc.mat')
    tracks = nrsfm.read(path)
    for k in (1, 3, 5, 8):
        run('frgc', 'frgc', k, tracks.W, tracks.mask, truth_path=path, threads=threads)


def face(shared, threads):
    path = os.path.join(shared, 'datasets', 'face.mat')
    tracks = nrsfm.read(path)
    for k in (4, 7):
        run('face', 'face', k, tracks.W, tracks.mask, truth_path=path, threads=threads)


PARTS = {'ksweep': ksweep, 'subsets': subsets, 'orbits': orbits, 'units': units,
         'frgc': frgc, 'face': face}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--shared', default=os.environ.get('NRSFM_SHARED_DIR', '../shared'))
    parser.add_argument('--parts', default=','.join(PARTS))
    parser.add_argument('--threads', type=int, default=2)
    parser.add_argument('--json', default='')
    parser.add_argument('--set', action='append', default=[], metavar='NAME=VALUE')
    args = parser.parse_args()
    for setting in args.set:
        name, _, value = setting.partition('=')
        try:
            OPTIONS[name] = float(value) if '.' in value or 'e' in value else int(value)
        except ValueError:
            OPTIONS[name] = value
    if not os.path.isdir(os.path.join(args.shared, 'datasets')):
        print('generalise: no %s/datasets (set --shared or NRSFM_SHARED_DIR)' % args.shared,
              file=sys.stderr)
        return 1
    for part in args.parts.split(','):
        if part not in PARTS:
            print('generalise: unknown part %r (%s)' % (part, ', '.join(PARTS)), file=sys.stderr)
            return 1
    for part in args.parts.split(','):
        PARTS[part](args.shared, args.threads)
    scored = [r for r in ROWS if 'ratio' in r]
    if scored:
        ratios = np.array([r['ratio'] for r in scored])
        print('object-frame runs: %d, ratio to the rank-K floor: median %.2f, max %.2f, '
              '%d above 2' % (len(scored), np.median(ratios), ratios.max(),
                              int(np.sum(ratios > 2.0))))
    limited = [r for r in ROWS if 'converged' in r and not r['converged']]
    print('runs: %d, at the iteration limit: %d, failed: %d' % (
        len(ROWS), len(limited), sum('error' in r for r in ROWS)))
    if args.json:
        with open(args.json, 'w') as out:
            json.dump(ROWS, out, indent=1)
    return 0


if __name__ == '__main__':
    sys.exit(main())
