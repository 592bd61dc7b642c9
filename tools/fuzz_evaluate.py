#!/usr/bin/env python3
"""Mutation fuzzing of `hazmap evaluate` over its JDEM inputs (issue 37).

Usage:
  tools/fuzz_evaluate.py HAZMAP N SEED [--work DIR] [--run DIR --sequence DIR]
                         [--timeout S] [--first K | --only I,J,...]

  HAZMAP   a hazmap binary, best one built by tools/sanitize.sh (ASan + UBSan)
  N SEED   number of cases and the seed of the mutations (same seed: same cases)
  --work   scratch folder (default /tmp/fuzz_evaluate); wiped per case
  --run/--sequence  inputs to mutate; without them the tool makes a small pair once into
           WORK/base: hazmap simulate --scenario rocks --seed 1 --frames 2 --scale 0.25
           --ground-truth, then hazmap run --config config/default.yaml
  --first K  start at case K (to run a long fuzz in chunks; the cases do not depend on it)
  --only I,J,...  run just these cases (to replay a failure)

Each case copies the inputs, mutates one line of one JDEM (a frame's layer of the run, or
the sequence's ground truth): one token replaced by a special value (nan, inf, 1e39, an
integer out of range, empty, garbage), the line deleted, or one character replaced; then
runs `hazmap evaluate --error-maps all --quiet` into an OUT that already holds a previous
evaluation. A case passes when it exits 0, or exits non-zero with exactly one line on
stderr and OUT byte-identical to before; it fails on any sanitizer report, a signal, a
timeout, a multi-line or empty error, or a touched OUT. Prints failing cases and a summary
(exit codes, error classes, time); exits 1 if any case failed. Standard library only.
"""
import argparse
import collections
import hashlib
import os
import random
import re
import shutil
import subprocess
import sys
import time

SPECIALS = ['nan', '-nan', 'inf', '-inf', '1e39', '-1e39', '3', '-1', '2.5', '1e308',
            '2147483648', '-2147483649', '', 'x', '0x10', '1e-320']
SANITIZER_MARKS = ('runtime error', 'AddressSanitizer', 'LeakSanitizer', 'UndefinedBehaviorSanitizer')


def snapshot(folder):
    """Name -> (size, sha1) of every file under folder (empty when it does not exist)."""
    out = {}
    for dp, _, fs in os.walk(folder):
        for f in fs:
            p = os.path.join(dp, f)
            with open(p, 'rb') as fh:
                out[os.path.relpath(p, folder)] = hashlib.sha1(fh.read()).hexdigest()
    return out


def make_inputs(hz, base, repo):
    """A two-frame simulated sequence with ground truth and its run, made once."""
    seq, run = os.path.join(base, 'seq'), os.path.join(base, 'run')
    if os.path.exists(os.path.join(run, 'summary.json')):
        return run, seq
    shutil.rmtree(base, ignore_errors=True)
    os.makedirs(base)
    subprocess.run([hz, 'simulate', '--scenario', 'rocks', '--seed', '1', '--frames', '2',
                    '--scale', '0.25', '--ground-truth', '--out', seq], check=True)
    subprocess.run([hz, 'run', '--config', os.path.join(repo, 'config', 'default.yaml'),
                    '--sequence', seq, '--out', run, '--quiet'], check=True)
    return run, seq


def error_class(line):
    """The message with numbers, paths and quoted text blanked, to group like errors."""
    line = re.sub(r'/\S+', 'PATH', line)
    line = re.sub(r"'[^']*'|\"[^\"]*\"", 'Q', line)
    line = re.sub(r'-?\d+(\.\d+)?(e[-+]?\d+)?', 'N', line)
    return line[:140]


def mutate(rnd, target):
    with open(target) as fh:
        lines = fh.read().split('\n')
    k = rnd.randrange(len(lines))
    toks = lines[k].split(' ')
    mode = rnd.random()
    if mode < 0.6 and toks:
        toks[rnd.randrange(len(toks))] = rnd.choice(SPECIALS)
        lines[k] = ' '.join(toks)
    elif mode < 0.8:
        del lines[k]
    else:
        s = lines[k]
        if s:
            j = rnd.randrange(len(s))
            lines[k] = s[:j] + chr(rnd.randrange(32, 127)) + s[j + 1:]
    with open(target, 'w') as fh:
        fh.write('\n'.join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('hazmap')
    ap.add_argument('n', type=int)
    ap.add_argument('seed', type=int)
    ap.add_argument('--work', default='/tmp/fuzz_evaluate')
    ap.add_argument('--run')
    ap.add_argument('--sequence')
    ap.add_argument('--timeout', type=float, default=60.0)
    ap.add_argument('--first', type=int, default=0)
    ap.add_argument('--only', help='comma-separated case numbers')
    a = ap.parse_args()
    hz = os.path.abspath(a.hazmap)
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if a.run and a.sequence:
        run, seq = os.path.abspath(a.run), os.path.abspath(a.sequence)
    else:
        run, seq = make_inputs(hz, os.path.join(a.work, 'base'), repo)

    env = dict(os.environ, ASAN_OPTIONS='abort_on_error=0:halt_on_error=0',
               UBSAN_OPTIONS='print_stacktrace=1:halt_on_error=0')
    w = os.path.join(a.work, 'case')
    ev = os.path.join(w, 'ev')

    def evaluate():
        return subprocess.run([hz, 'evaluate', '--run', w + '/run', '--sequence', w + '/seq',
                               '--out', ev, '--error-maps', 'all', '--quiet'],
                              capture_output=True, text=True, env=env, timeout=a.timeout)

    # A clean evaluation of the unmutated inputs: OUT's contents before every case.
    shutil.rmtree(w, ignore_errors=True)
    shutil.copytree(run, w + '/run')
    shutil.copytree(seq, w + '/seq')
    r = evaluate()
    if r.returncode != 0:
        sys.exit('unmutated inputs fail: ' + r.stderr)
    ev_before = os.path.join(a.work, 'ev_before')
    shutil.rmtree(ev_before, ignore_errors=True)
    shutil.copytree(ev, ev_before)
    before = snapshot(ev_before)

    files = sorted(os.path.relpath(os.path.join(dp, f), run)
                   for dp, _, fs in os.walk(run) for f in fs if f.endswith('.jdem'))
    targets = ['run/' + f for f in files] + ['seq/gt_height.jdem', 'seq/gt_hazard.jdem']
    codes, classes, failures = collections.Counter(), collections.Counter(), []
    t0 = time.time()
    cases = [int(c) for c in a.only.split(',')] if a.only else range(a.first, a.first + a.n)
    for done, i in enumerate(cases, 1):
        rnd = random.Random(f'{a.seed}:{i}')
        shutil.rmtree(w, ignore_errors=True)
        shutil.copytree(run, w + '/run')
        shutil.copytree(seq, w + '/seq')
        shutil.copytree(ev_before, ev)
        target = rnd.choice(targets)
        mutate(rnd, os.path.join(w, target))
        t_case = time.time()
        try:
            r = evaluate()
        except subprocess.TimeoutExpired:
            codes['timeout'] += 1
            failures.append((i, target, 'timeout'))
            print(f'FAIL case {i} {target}: no answer in {a.timeout:g} s', flush=True)
            continue
        if a.only:
            print(f'case {i} {target}: exit {r.returncode} in {time.time() - t_case:.1f} s: '
                  f'{r.stderr.strip()[:300]}', flush=True)
        codes[r.returncode] += 1
        out = r.stdout + r.stderr
        err_lines = [l for l in r.stderr.split('\n') if l.strip()]
        why = None
        if any(m in out for m in SANITIZER_MARKS):
            why = 'sanitizer report'
        elif r.returncode < 0:
            why = f'signal {-r.returncode}'
        elif r.returncode != 0 and len(err_lines) != 1:
            why = f'{len(err_lines)} stderr lines'
        elif r.returncode != 0 and snapshot(ev) != before:
            why = 'OUT touched'
        if r.returncode > 0 and err_lines:
            classes[error_class(err_lines[0])] += 1
        if why:
            failures.append((i, target, why))
            print(f'FAIL case {i} {target}: {why}\n{out[:1500]}', flush=True)
        if done % 100 == 0 and done < len(cases):
            print(f'{done} cases, {len(failures)} failed, {time.time() - t0:.0f} s', flush=True)
    dt = time.time() - t0
    span = a.only if a.only else f'{a.first}..{a.first + a.n - 1}'
    print(f'cases {span} seed {a.seed}: {len(failures)} failed, exit codes {dict(codes)}, '
          f'{dt:.0f} s ({dt / max(len(cases), 1):.2f} s/case)')
    for c, k in classes.most_common():
        print(f'  {k:5d}  {c}')
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
