#!/usr/bin/env python3
"""Agreement with piglit's own runner beyond ../shared: a stratified sample of the installed
piglit package's shader_test files, run by piglit's shader_runner and by parity, tabulated.

    apt-get install piglit      # Debian 12: about 2 GB under /usr/lib/x86_64-linux-gnu/piglit
    python3 scripts/piglit_sample.py --parity build/parity --size 600 --seed 20261206

Only the even half of the package is drawn from (first hex digit of the sha1 of the path inside
the package even), less the files of ../shared/peer-cases/piglit-oracle; the odd half is left
alone to measure generality later. Folders (tests/spec/X, generated_tests/spec/X) are sampled in
proportion to the square root of their size, as the oracle folder was. Prints, per backend, the
count of each (piglit verdict, parity result) pair and lists parity's FAILs where piglit does not
fail.
"""
import argparse
import collections
import hashlib
import json
import math
import os
import random
import re
import subprocess
import sys

PIGLIT = "/usr/lib/x86_64-linux-gnu/piglit"


def draw(size, seed, oracle_tsv, match=None):
    oracle = set()
    if os.path.exists(oracle_tsv):
        oracle = {line.split("\t")[0] for line in open(oracle_tsv)}
    groups = collections.defaultdict(list)
    for top in ("tests", "generated_tests"):
        for folder, _, names in os.walk(os.path.join(PIGLIT, top)):
            for name in names:
                if not name.endswith(".shader_test"):
                    continue
                path = os.path.relpath(os.path.join(folder, name), PIGLIT)
                if match and not re.search(match, path):
                    continue
                if int(hashlib.sha1(path.encode()).hexdigest()[0], 16) % 2 == 0 and path not in oracle:
                    groups["/".join(path.split("/")[:3])].append(path)
    if match:  # every file of the even half that matches, not a sample
        return sorted(p for files in groups.values() for p in files)
    rng = random.Random(seed)
    total = sum(math.sqrt(len(v)) for v in groups.values())
    sample = []
    for key in sorted(groups):
        files = groups[key]
        sample += rng.sample(files, min(len(files), max(1, round(size * math.sqrt(len(files)) / total))))
    return sorted(sample)


def piglit_verdict(path):
    env = dict(os.environ, PIGLIT_PLATFORM="surfaceless_egl")
    try:
        out = subprocess.run([os.path.join(PIGLIT, "bin/shader_runner"), path, "-auto", "-fbo"], cwd=PIGLIT, env=env,
                             capture_output=True, text=True, timeout=60).stdout
    except subprocess.TimeoutExpired:
        return "timeout"
    for line in reversed(out.splitlines()):
        if '"result"' in line:
            return line.split('"result"')[1].split('"')[1]
    return "crash"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--parity", default=os.path.join(here, "..", "build", "parity"))
    ap.add_argument("--size", type=int, default=600)
    ap.add_argument("--seed", type=int, default=20261206)
    ap.add_argument("--match", help="every even-half file whose path matches this regular expression, instead of a sample")
    ap.add_argument("--list", action="store_true", help="also print each file piglit passes and parity does not, with the reason")
    ap.add_argument("--oracle", default=os.path.join(here, "..", "..", "shared", "peer-cases", "piglit-oracle", "verdicts.tsv"))
    args = ap.parse_args()
    if not os.path.isdir(PIGLIT):
        sys.exit(f"{PIGLIT}: not installed (apt-get install piglit)")
    sample = draw(args.size, args.seed, args.oracle, args.match)
    theirs = {path: piglit_verdict(path) for path in sample}
    run = subprocess.run([os.path.abspath(args.parity), "test", *sample, "--platform", "reference", "--json", "--timeout", "300"],
                         cwd=PIGLIT, capture_output=True, text=True)
    cases = json.loads(run.stdout)["cases"]
    table = collections.defaultdict(collections.Counter)
    wrong, short = [], []
    for c in cases:
        verdict = theirs[c["script"]]
        table[c["backend"]][(verdict, c["result"])] += 1
        if c["result"] == "FAIL" and verdict != "fail":
            wrong.append(f'{c["backend"]} {c["script"]}: {c.get("reason", "")[:200]}')
        elif verdict == "pass" and c["result"] != "PASS":
            short.append(f'{c["backend"]} {c["result"]} {c["script"]}: {c.get("reason", "")[:200]}')
    drawn = f"matching {args.match}" if args.match else f"(seed {args.seed})"
    print(f"{len(sample)} files {drawn}; piglit: {dict(collections.Counter(theirs.values()))}")
    for backend in sorted(table):
        for (verdict, result), n in sorted(table[backend].items()):
            print(f"{backend}: piglit {verdict}, parity {result}: {n}")
    for line in wrong:
        print("FAIL where piglit does not fail:", line)
    if args.list:
        for line in sorted(short):
            print("piglit passes:", line)


if __name__ == "__main__":
    main()
