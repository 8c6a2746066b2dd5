"""Merges the repeated runs of tools/charts: accuracy_K.json and llvmpipe[_models]_K.json in RUNS
into OUT/accuracy.json and OUT/llvmpipe[_models].json, each timing the median of the runs with its
spread (the errors are deterministic: they come from the first run, and a run that disagrees on
them is reported).

usage: merge_runs.py RUNS OUT N
"""
import json
import os
import statistics
import sys

RUNS, OUT, N = sys.argv[1], sys.argv[2], int(sys.argv[3])


def load(name):
    path = os.path.join(RUNS, name)
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def spread(rows_by_run, key):
    values = [r[key] for r in rows_by_run]
    return statistics.median(values), min(values), max(values)


# accuracy: rows in the same order every run
runs = [load(f"accuracy_{k}.json") for k in range(1, N + 1)]
merged = runs[0]
for i, row in enumerate(merged["rows"]):
    same = [run["rows"][i] for run in runs]
    for other in same[1:]:
        if (other["method"], other["item"], other["max_lsb"]) != (row["method"], row["item"], row["max_lsb"]):
            print(f"merge_runs: accuracy row {i} differs between runs: {row['method']} {row['item']}", file=sys.stderr)
    for key in ("ms_per_frame", "rate"):
        row[key], row[key + "_min"], row[key + "_max"] = spread(same, key)
merged["runs"] = N
with open(os.path.join(OUT, "accuracy.json"), "w") as f:
    json.dump(merged, f, indent=1)

# llvmpipe comparisons: rows by name
for base in ("llvmpipe", "llvmpipe_models"):
    runs = [load(f"{base}_{k}.json") for k in range(1, N + 1)]
    if runs[0] is None:
        continue
    rows = []
    for row in runs[0]:
        same = [next(r for r in run if r["name"] == row["name"]) for run in runs if run]
        for key in ("facet_ms", "llvmpipe_ms"):
            row[key], row[key + "_min"], row[key + "_max"] = spread(same, key)
        row["ratio"] = row["llvmpipe_ms"] / row["facet_ms"] if row["facet_ms"] > 0 else 0
        row["runs"] = len(same)
        rows.append(row)
    with open(os.path.join(OUT, base + ".json"), "w") as f:
        json.dump(rows, f, indent=1)
print(f"merge_runs: medians of {N} runs written to {OUT}")
