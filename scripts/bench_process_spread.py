#!/usr/bin/env python3
"""Do a `parity bench` run's processes differ as a whole, or only by the spread of their rounds?

    python3 scripts/bench_process_spread.py OUT/lidr-overlap-1/lidr-overlap.json [more STUDY.json ...]

For every point and technique measured in several processes (`process_rounds` in STUDY.json),
takes the Vulkan / GL ratio of each round (each device's frame time over the first device's, for
`--devices` runs), and compares the range of the processes' medians with the same range after the
rounds are shuffled between the processes (2,000 shuffles, seeded). A small p (below 0.05) says the
processes' medians lie further apart than their rounds alone would put them: something about a
process as a whole (its heap, its threads) moved its frames. Prints one line per point and
technique and the count of small p; by chance alone about 1 in 20 is small.
"""
import argparse
import json
import random
import statistics


def per_process(ratios, process_rounds):
    parts, at = [], 0
    for n in process_rounds:
        parts.append(ratios[at:at + n])
        at += n
    return parts


def median_range(parts):
    medians = [statistics.median(p) for p in parts if p]
    return max(medians) - min(medians)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("studies", nargs="+", help="STUDY.json files of parity bench runs")
    ap.add_argument("--shuffles", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    draw = random.Random(args.seed)
    small = total = 0
    for path in args.studies:
        try:
            with open(path) as f:
                study = json.load(f)
            devices = study["plan"].get("devices") or ["gl", "vk"]
            rows = [r for r in study["rows"] if r["status"] == "ok"]
        except (OSError, ValueError, KeyError) as e:
            raise SystemExit(f"{path}: not the STUDY.json of a parity bench run ({e})")
        key = lambda r: (r["technique"], r["scenario"], r["x"], r["params"])
        first = {key(r): r for r in rows if r["backend"] == devices[0]}
        for r in rows:
            ref = first.get(key(r))
            if r["backend"] == devices[0] or not ref or len(r.get("process_rounds", [])) < 2:
                continue
            if r["process_rounds"] != ref.get("process_rounds"):
                continue
            ratios = [b / a for a, b in zip(ref["frames"], r["frames"]) if a > 0]
            if len(ratios) != len(r["frames"]):
                continue
            observed = median_range(per_process(ratios, r["process_rounds"]))
            wider = 0
            for _ in range(args.shuffles):
                shuffled = ratios[:]
                draw.shuffle(shuffled)
                wider += median_range(per_process(shuffled, r["process_rounds"])) >= observed
            p = (wider + 1) / (args.shuffles + 1)  # the observed split counts as one of the shuffles
            total += 1
            small += p < 0.05
            print(f"{path}: {r['backend']}/{devices[0]} {r['technique']} {r['scenario']} x={r['x']:g}: "
                  f"process medians {observed:.3f} apart, p={p:.3f} ({r['process_rounds'][0]} rounds a process)")
    print(f"{small} of {total} point ratios with p < 0.05")


if __name__ == "__main__":
    main()
