"""Draws facet's charts and the summary table from bench/results/*.json (see tools/charts).

Run by Debian's /usr/bin/python3 with python3-matplotlib; no other dependency.
"""
import json
import os
import platform
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = sys.argv[1]


def load(name):
    with open(os.path.join(OUT, name)) as f:
        return json.load(f)


lighting = load("lighting.json")
frames = load("frames.json")
accuracy = load("accuracy.json")["rows"]


def bench_rows(doc):
    """One row per benchmark: with --benchmark_repetitions, each numeric field is the median of the
    repetitions and row["_spread"][field] its (min, max)."""
    groups = {}
    for b in doc["benchmarks"]:
        if b.get("run_type", "iteration") != "iteration" or "error_occurred" in b:
            continue
        groups.setdefault(b.get("run_name", b["name"]), []).append(b)
    rows = []
    for name, runs in groups.items():
        row = dict(runs[0])
        row["name"] = name
        row["_spread"] = {}
        for key, value in runs[0].items():
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                values = sorted(r[key] for r in runs if key in r)
                n = len(values)
                row[key] = values[n // 2] if n % 2 else 0.5 * (values[n // 2 - 1] + values[n // 2])
                row["_spread"][key] = (values[0], values[-1])
        row["_runs"] = len(runs)
        rows.append(row)
    return rows


def spread_of(row, key, scale=1.0):
    """Error-bar extents (below, above) of a median from its spread, scaled."""
    lo, hi = row.get("_spread", {}).get(key, (row[key], row[key]))
    return (row[key] - lo) / scale, (hi - row[key]) / scale


def method_label(bench_method):
    """Benchmark method name -> the accuracy harness's name ("simd_avx2_fast" -> "simd avx2 (pow fast)")."""
    if bench_method.startswith("simd_"):
        _, isa, tier = bench_method.split("_", 2)
        return f"simd {isa} (pow {tier})"
    return bench_method


def pareto(points):
    """Points (x, y, ...) not dominated by another with larger-or-equal x and smaller-or-equal y."""
    front = [p for p in points if not any(q[0] >= p[0] and q[1] <= p[1] and (q[0], q[1]) != (p[0], p[1]) for q in points)]
    return sorted(front, key=lambda p: p[0])


ISA_COLOURS = {"reference": "#555555", "scalar": "#1f77b4", "sse2": "#2ca02c", "avx2": "#d62728", "avx512": "#9467bd"}
TIER_MARKERS = {"auto": "o", "exact": "s", "fast": "^", "integer": "D", "schlick": "x"}
MODE_COLOURS = {"flat": "#1f77b4", "gouraud": "#ff7f0e", "phong": "#2ca02c"}


def save(fig, name):
    fig.savefig(os.path.join(OUT, name + ".png"), dpi=110)
    fig.savefig(os.path.join(OUT, name + ".svg"))
    plt.close(fig)


# --- 1. speed vs accuracy -------------------------------------------------------------------------
vertex_error = {r["method"]: r["max_lsb"] for r in accuracy if r["kind"] == "vertices" and r["item"] == "random"}
FLOOR = 1e-5  # the reference is the oracle: its error is 0, drawn at this floor
points = []
for b in bench_rows(lighting):
    parts = b["name"].split("/")
    if parts[2] != "mixed" or parts[3] != "lights:4" or parts[4] != "vertices:4096":
        continue
    method = parts[1]
    label = method_label(method)
    err = 0.0 if method == "reference" else vertex_error.get(label)
    if err is None:
        continue
    points.append((b["vertex_lights/s"], max(err, FLOOR), label, method))

# The specular lobes: Blinn's n.h and Phong's R.V per method (BM_LightingLobe), against the
# accuracy harness's "random" and "random, phong lobe" rows.
lobe_error = {("blinn", r["method"]): r["max_lsb"] for r in accuracy if r["kind"] == "vertices" and r["item"] == "random"}
lobe_error.update({("phong", r["method"]): r["max_lsb"] for r in accuracy
                   if r["kind"] == "vertices" and r["item"] == "random, phong lobe"})
lobe_points = []
for b in bench_rows(lighting):
    parts = b["name"].split("/")
    if parts[0] != "BM_LightingLobe":
        continue
    method, lobe = parts[1], parts[2]
    err = 0.0 if method == "reference" else lobe_error.get((lobe, method_label(method)))
    if err is None:
        continue
    lobe_points.append((b["vertex_lights/s"], max(err, FLOOR), lobe, method))

fig, (ax1, ax2, ax3, ax4) = plt.subplots(1, 4, figsize=(28, 6))
for x, y, label, method in points:
    isa = "reference" if method == "reference" else ("scalar" if method == "scalar" else method.split("_")[1])
    tier = method.split("_")[2] if method.startswith("simd_") else "auto"
    ax1.scatter(x / 1e6, y, color=ISA_COLOURS[isa], marker=TIER_MARKERS[tier], s=60, zorder=3)
front = pareto(points)
ax1.plot([p[0] / 1e6 for p in front], [p[1] for p in front], "--", color="black", lw=1, zorder=2, label="Pareto front")
for x, y, label, method in front:
    if method != "reference":
        ax1.annotate(label.replace("simd ", ""), (x / 1e6, y), textcoords="offset points", xytext=(6, 4), fontsize=8)
ax1.set_xlim(0, max(p[0] for p in points) / 1e6 * 1.25)
ax1.set_yscale("log")
ax1.set_xlabel("vertex-lights per second (millions, 1 thread, 4 mixed lights, 4096 vertices)")
ax1.set_ylabel("largest error vs the double-precision reference (8-bit steps)")
ax1.set_title("Vertex lighting: path x ISA x pow tier")
handles = [plt.Line2D([], [], color=c, marker="o", ls="", label=k) for k, c in ISA_COLOURS.items()
           if any((p[3] == k) or (k in p[3].split("_")) for p in points)]
handles += [plt.Line2D([], [], color="black", marker=m, ls="", label="pow " + t) for t, m in TIER_MARKERS.items()]
handles.append(plt.Line2D([], [], color="black", ls="--", label="Pareto front"))
ax1.legend(handles=handles, fontsize=8, loc="upper left")
ax1.axhline(FLOOR, color="#999999", lw=0.5)
ax1.annotate("reference: error 0 (drawn at 1e-5)", (ax1.get_xlim()[1], FLOOR), textcoords="offset points",
             xytext=(-4, 4), fontsize=7, color="#666666", ha="right")
ax1.axhline(0.5, color="#bbbbbb", lw=0.8, ls=":")
ax1.annotate("half an 8-bit step", (ax1.get_xlim()[1], 0.5), textcoords="offset points", xytext=(-4, 4), fontsize=7,
             color="#666666", ha="right")
ax1.grid(True, which="both", alpha=0.2)

image_points = []
for r in accuracy:
    if r["kind"] != "image" or not r.get("ms_per_frame"):
        continue
    seg = int(r["item"].split("=")[1])
    image_points.append((1000.0 / r["ms_per_frame"], max(r["mean_lsb"], 1e-4), r["method"].split()[0], seg, r["psnr_db"]))
for mode in MODE_COLOURS:
    pts = sorted([p for p in image_points if p[2] == mode], key=lambda p: p[3])
    ax2.plot([p[0] for p in pts], [p[1] for p in pts], "-o", color=MODE_COLOURS[mode], label=mode, ms=5)
    for p in pts:
        ax2.annotate(str(p[3]), (p[0], p[1]), textcoords="offset points", xytext=(4, -10), fontsize=7,
                     color=MODE_COLOURS[mode])
front = pareto(image_points)
ax2.plot([p[0] for p in front], [p[1] for p in front], "--", color="black", lw=1, label="Pareto front")
ax2.set_xscale("log")
ax2.set_yscale("log")
ax2.set_xlabel("frames per second (640x400, simd path, 1 thread)")
ax2.set_ylabel("mean error inside silhouettes vs ray-cast spheres (8-bit steps)")
ax2.set_title("Shading modes x tessellation (labels: sphere segments)")
ax2.legend(fontsize=8)
ax2.grid(True, which="both", alpha=0.2)
texture_points = [r for r in accuracy if r["kind"] == "texture" and r.get("rate")]
FILTER_COLOURS = {"nearest": "#1f77b4", "bilinear": "#ff7f0e", "trilinear": "#2ca02c"}
ISA_MARKERS = {"scalar": "o", "sse2": "s", "avx2": "^", "avx512": "D"}
for r in texture_points:
    parts = r["method"].split()  # "scalar", "simd ISA" or "simd ISA 16-bit" (the fixed-point sampler: open)
    isa = parts[1] if parts[0] == "simd" else parts[0]
    fixed = parts[-1] == "16-bit"
    colour = FILTER_COLOURS.get(r["item"], "black")
    ax3.scatter(r["rate"] / 1e6, max(r["max_lsb"], FLOOR), color=colour, facecolors="none" if fixed else colour,
                marker=ISA_MARKERS.get(isa, "x"), s=60, zorder=3)
ax3.set_yscale("log")
ax3.set_xlabel("texture samples per second (millions, 1 thread, 256x256, random LOD -2..7)")
ax3.set_ylabel("largest error vs the double-precision reference sampler (8-bit steps)")
ax3.set_title("Texture filters: float samplers (filled), 16-bit tier's fixed point (open)")
ax3.axhline(1.0, color="#bbbbbb", lw=0.8, ls=":")
ax3.annotate("contract: 1 step", (0, 1.0), textcoords="offset points", xytext=(4, 4), fontsize=7, color="#666666")
handles = [plt.Line2D([], [], color=c, marker="o", ls="", label=k) for k, c in FILTER_COLOURS.items()]
handles += [plt.Line2D([], [], color="black", marker=m, ls="", label=k) for k, m in ISA_MARKERS.items()]
ax3.legend(handles=handles, fontsize=8, loc="upper right")
ax3.grid(True, which="both", alpha=0.2)
LOBE_MARKERS = {"blinn": "o", "phong": "^"}
for x, y, lobe, method in lobe_points:
    isa = "reference" if method == "reference" else ("scalar" if method == "scalar" else method.split("_")[1])
    ax4.scatter(x / 1e6, y, color=ISA_COLOURS[isa], marker=LOBE_MARKERS[lobe], s=60, zorder=3,
                facecolors="none" if lobe == "phong" else ISA_COLOURS[isa])
ax4.set_yscale("log")
ax4.set_xlabel("vertex-lights per second (millions, 1 thread, 4 mixed lights, 4096 vertices)")
ax4.set_ylabel("largest error vs the double-precision reference (8-bit steps)")
ax4.set_title("Specular lobes: Blinn n.h (filled) and Phong R.V (open)")
handles = [plt.Line2D([], [], color=c, marker="o", ls="", label=k) for k, c in ISA_COLOURS.items()]
handles += [plt.Line2D([], [], color="black", marker=m, ls="", label=k, markerfacecolor="none" if k == "phong" else "black")
            for k, m in LOBE_MARKERS.items()]
ax4.legend(handles=handles, fontsize=8, loc="upper left")
ax4.axhline(FLOOR, color="#999999", lw=0.5)
ax4.grid(True, which="both", alpha=0.2)
fig.suptitle("facet: speed against accuracy", fontsize=13)
fig.tight_layout()
save(fig, "speed_vs_accuracy")

# --- 2. scalar vs SIMD ----------------------------------------------------------------------------
light_rate = {}
light_err = {}
for b in bench_rows(lighting):
    parts = b["name"].split("/")
    if parts[2] == "mixed" and parts[3] == "lights:4" and parts[4] == "vertices:4096":
        light_rate[parts[1]] = b["vertices_lit/s"]
        light_err[parts[1]] = spread_of(b, "vertices_lit/s", 1e6)
order = ["reference", "scalar"] + [m for m in ("simd_sse2_auto", "simd_avx2_auto", "simd_avx512_auto") if m in light_rate]
fill = {}
fill_err = {}
for b in bench_rows(frames):
    parts = b["name"].split("/")
    if parts[0] == "BM_Fill" and parts[2] == "gouraud":
        fill[(parts[1], parts[3])] = b["pixels_filled/s"]
        fill_err[(parts[1], parts[3])] = spread_of(b, "pixels_filled/s", 1e9)
variants = [v for v in ("scalar", "sse2", "avx2", "avx512") if (v, "threads:1") in fill]

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.5))
xs = range(len(order))
vals = [light_rate[m] / 1e6 for m in order]
bars = ax1.bar(xs, vals, color=[ISA_COLOURS["reference"], ISA_COLOURS["scalar"]] +
               [ISA_COLOURS[m.split("_")[1]] for m in order[2:]],
               yerr=[[light_err[m][0] for m in order], [light_err[m][1] for m in order]], capsize=4, ecolor="#333333")
for bar, m in zip(bars, order):
    ax1.annotate(f"{light_rate[m] / light_rate['scalar']:.1f}x", (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                 ha="center", va="bottom", fontsize=9)
ax1.set_xticks(list(xs))
ax1.set_xticklabels([m.replace("simd_", "").replace("_auto", " (auto)") for m in order])
ax1.set_ylabel("vertices lit per second (millions)")
ax1.set_title("Vertex lighting, 1 thread, 4 mixed lights\n(labels: speed-up over scalar; bars: median, whiskers: min-max of the runs)")
ax1.grid(True, axis="y", alpha=0.3)
width = 0.38
for k, threads in enumerate(("threads:1", "threads:2")):
    vals = [fill.get((v, threads), 0) / 1e9 for v in variants]
    pos = [i + (k - 0.5) * width for i in range(len(variants))]
    bars = ax2.bar(pos, vals, width, label=threads.replace("threads:", "") + (" thread" if k == 0 else " threads"),
                   color=["#9ecae1", "#3182bd"][k],
                   yerr=[[fill_err.get((v, threads), (0, 0))[0] for v in variants],
                         [fill_err.get((v, threads), (0, 0))[1] for v in variants]], capsize=3, ecolor="#333333")
    for bar, v in zip(bars, variants):
        base = fill.get(("scalar", threads))
        if base:
            ax2.annotate(f"{fill[(v, threads)] / base:.1f}x", (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                         ha="center", va="bottom", fontsize=8)
ax2.axhline(2.4, color="#d62728", ls=":", lw=1)
ax2.set_ylim(0, max(2.8, max(fill.values()) / 1e9 * 1.15))
ax2.annotate("target: 2.4 G/s on 2 threads", (-0.4, 2.4), textcoords="offset points", xytext=(0, 4),
             fontsize=8, color="#d62728")
ax2.set_xticks(range(len(variants)))
ax2.set_xticklabels(variants)
ax2.set_ylabel("pixels filled per second (billions)")
ax2.set_title("Fill: 16 full-screen Gouraud layers, 1920x1080\n(labels: speed-up over scalar, same threads)")
ax2.legend(fontsize=9, loc="center left")
ax2.grid(True, axis="y", alpha=0.3)
fig.tight_layout()
save(fig, "scalar_vs_simd")

# --- 3. thread scaling ------------------------------------------------------------------------------
best = variants[-1]
scaling = {}
for b in bench_rows(frames):
    parts = b["name"].split("/")
    if parts[1] != best:
        continue
    key = "/".join(parts[2:-2]) if parts[0] == "BM_Frame" else "fill " + parts[2]
    scaling.setdefault(key, {})[parts[-2]] = b["real_time"]
labels = [k for k in scaling if "threads:1" in scaling[k] and "threads:2" in scaling[k]]
labels.sort()
speedups = [scaling[k]["threads:1"] / scaling[k]["threads:2"] for k in labels]
fig, ax = plt.subplots(figsize=(12, 5.5))
bars = ax.bar(range(len(labels)), speedups, color="#3182bd")
for bar, k in zip(bars, labels):
    ax.annotate(f"{bar.get_height():.2f}x\n{scaling[k]['threads:2']:.1f} ms", (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                ha="center", va="bottom", fontsize=7)
ax.axhline(2.0, color="black", lw=0.8, ls="--")
ax.annotate("ideal (2 cores)", (len(labels) - 0.6, 2.0), textcoords="offset points", xytext=(0, 4), fontsize=8,
            ha="right")
ax.axhline(1.8, color="#d62728", lw=0.8, ls=":")
ax.annotate("target 1.8x", (len(labels) - 0.6, 1.8), textcoords="offset points", xytext=(0, -12), fontsize=8,
            color="#d62728", ha="right")
ax.set_xticks(range(len(labels)))
ax.set_xticklabels(labels, rotation=35, ha="right", fontsize=8)
ax.set_ylim(0, 2.5)
ax.set_ylabel("speed-up: 2 threads over 1")
ax.set_title(f"Thread scaling of whole frames, simd {best} (labels: speed-up, ms per frame on 2 threads)")
ax.grid(True, axis="y", alpha=0.3)
fig.tight_layout()
save(fig, "thread_scaling")

# --- 4. ms per frame against triangles, facet and llvmpipe ------------------------------------------
charts = ["speed_vs_accuracy", "scalar_vs_simd", "thread_scaling"]
rows = []
for name in ("llvmpipe.json", "llvmpipe_models.json"):
    if os.path.exists(os.path.join(OUT, name)):
        # fills are pixel-bound (32 triangles); of the 1/4/8-light cases only the 4-light ones (one point each)
        rows += [r for r in load(name) if not r["name"].startswith("fill_") and not r["name"].endswith(("_1lights", "_8lights"))]
if rows:
    fig, ax = plt.subplots(figsize=(9, 6))
    def ms_err(r, key):
        return [[r[key] - r.get(key + "_min", r[key])], [r.get(key + "_max", r[key]) - r[key]]]
    ax.scatter([r["triangles"] for r in rows], [r["facet_ms"] for r in rows], color="#9467bd", label="facet (simd, best ISA)")
    ax.scatter([r["triangles"] for r in rows], [r["llvmpipe_ms"] for r in rows], color="#7f7f7f", marker="s",
               label="llvmpipe (Mesa)")
    for r in rows:
        ax.errorbar([r["triangles"]], [r["facet_ms"]], yerr=ms_err(r, "facet_ms"), color="#9467bd", capsize=2, lw=0.8)
        ax.errorbar([r["triangles"]], [r["llvmpipe_ms"]], yerr=ms_err(r, "llvmpipe_ms"), color="#7f7f7f", capsize=2, lw=0.8)
    for r in rows:
        ax.plot([r["triangles"]] * 2, [r["facet_ms"], r["llvmpipe_ms"]], color="#cccccc", lw=0.8, zorder=0)
        ax.annotate(f"{r['name']} {r['ratio']:.1f}x", (r["triangles"], r["facet_ms"]), textcoords="offset points",
                    xytext=(4, -10), fontsize=6)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles")
    ax.set_ylabel("ms per frame")
    ax.set_title(f"Whole frames, {rows[0]['width']}x{rows[0]['height']}, {rows[0]['threads']} threads each "
                 "(labels: llvmpipe ms / facet ms)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    save(fig, "frames_vs_triangles")
    charts.append("frames_vs_triangles")

# --- 5. shadow methods: ms per frame against pixels that differ from ray-cast shadows ----------------
shadow_rows = [r for r in accuracy if r["kind"] == "shadow"]
if shadow_rows:
    SHADOW_FLOOR = 1e-3  # ray-cast shadows are the reference: no pixel differs, drawn at this floor (%)
    FILTER_MARKERS = {"none": "s", "pcf2x2": "^", "pcf3x3": "o", "pcf5x5": "D"}
    LIGHT_COLOURS = {"directional": "#ff7f0e", "spot": "#2ca02c", "point": "#9467bd"}
    fig, ax = plt.subplots(figsize=(10, 6.5))
    for r in shadow_rows:  # the spread of the runs' frame times (tools/charts runs each at least 3 times)
        if "ms_per_frame_min" in r:
            ax.errorbar([max(100.0 * r["share"], SHADOW_FLOOR)], [r["ms_per_frame"]],
                        yerr=[[r["ms_per_frame"] - r["ms_per_frame_min"]], [r["ms_per_frame_max"] - r["ms_per_frame"]]],
                        color="#aaaaaa", lw=0.7, capsize=2, zorder=1)
    for r in shadow_rows:
        light = r["item"].split()[0]
        share = max(100.0 * r["share"], SHADOW_FLOOR)
        if r["method"] == "raycast":
            ax.scatter([share], [r["ms_per_frame"]], color=LIGHT_COLOURS[light], marker="*", s=160, edgecolors="black",
                       linewidths=0.6, zorder=3)
            ax.annotate(f"ray-cast ({light})", (share, r["ms_per_frame"]), textcoords="offset points", xytext=(6, -3),
                        fontsize=7)
            continue
        if r["method"] == "volume":
            ax.scatter([share], [r["ms_per_frame"]], color=LIGHT_COLOURS[light], marker="P", s=110, edgecolors="black",
                       linewidths=0.6, zorder=3)
            ax.annotate(f"volume ({light})", (share, r["ms_per_frame"]), textcoords="offset points", xytext=(6, 2),
                        fontsize=7)
            continue
        filt = r["method"].split()[1]
        ax.scatter([share], [r["ms_per_frame"]], color=LIGHT_COLOURS[light], marker=FILTER_MARKERS[filt], s=28,
                   alpha=0.85)
        ax.annotate(r["item"].split()[1], (share, r["ms_per_frame"]), textcoords="offset points", xytext=(3, 2),
                    fontsize=5, color="#555555")
    for light, colour in LIGHT_COLOURS.items():
        ax.scatter([], [], color=colour, marker="o", label=f"{light} light")
    for filt, marker in FILTER_MARKERS.items():
        ax.scatter([], [], color="#777777", marker=marker, label=f"map, {filt}")
    ax.scatter([], [], color="#777777", marker="P", s=90, label="stencil volumes (exact per pixel)")
    ax.scatter([], [], color="#777777", marker="*", s=120, label="ray-cast (exact; 0 %, drawn at the floor)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("receiver pixels that differ from ray-cast shadows (%)")
    ax.set_ylabel("ms per frame (640x360, Phong, 1 thread)")
    ax.set_title(f"Shadow methods: cost against error (labels: map resolution; simd {best})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    save(fig, "shadows_speed_vs_accuracy")
    charts.append("shadows_speed_vs_accuracy")

def per_vertex_and_pixel(rows, colours, xlabel, ylabel, title, name):
    """ms per frame against mean error, one line per method, each point labelled by its segments."""
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for method, colour in colours.items():
        pts = sorted([r for r in rows if r["method"] == method], key=lambda r: int(r["item"].split("=")[1]))
        ax.plot([max(r["mean_lsb"], FLOOR) for r in pts], [r["ms_per_frame"] for r in pts], color=colour, marker="o",
                label=method)
        for r in pts:
            if "ms_per_frame_min" in r:
                ax.errorbar([max(r["mean_lsb"], FLOOR)], [r["ms_per_frame"]],
                            yerr=[[r["ms_per_frame"] - r["ms_per_frame_min"]], [r["ms_per_frame_max"] - r["ms_per_frame"]]],
                            color=colour, lw=0.7, capsize=2)
            ax.annotate(r["item"].split("=")[1], (max(r["mean_lsb"], FLOOR), r["ms_per_frame"]), textcoords="offset points",
                        xytext=(4, 3), fontsize=7, color=colour)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, name)
    charts.append(name)


# --- 6. environment maps: per vertex against per pixel, ms per frame against error ------------------
env_rows = [r for r in accuracy if r["kind"] == "environment"]
if env_rows:
    per_vertex_and_pixel(env_rows, {"per vertex (gouraud)": "#1f77b4", "per pixel (phong)": "#d62728"},
                         "mean error against exact reflection rays (8-bit steps)", "ms per frame (1 thread)",
                         f"Environment maps on a mirror ball (labels: segments; simd {best})", "environment_speed_vs_accuracy")

# --- 7. bump maps: per vertex against per pixel, ms per frame against error -------------------------
relief_rows = [r for r in accuracy if r["kind"] == "relief"]
if relief_rows:
    per_vertex_and_pixel(relief_rows, {"bump per vertex (gouraud)": "#1f77b4", "bump per pixel (phong)": "#d62728"},
                         "mean error against per-pixel bump on the reference path, 512 segments (8-bit steps)",
                         "ms per frame (480x480, 1 thread)",
                         f"Bump maps per vertex and per pixel (labels: segments; simd {best})", "relief_speed_vs_accuracy")

# --- 7b. PBR materials under the studio: per vertex against per pixel ----------------------------------
pbr_rows = [r for r in accuracy if r["kind"] == "pbr"]
if pbr_rows:
    per_vertex_and_pixel(pbr_rows, {"PBR per vertex (gouraud)": "#1f77b4", "PBR per pixel (phong)": "#d62728"},
                         "mean error against the reference path per pixel, 512 segments (8-bit sRGB steps)",
                         "ms per frame (720x240, 1 thread)",
                         f"PBR under the neutral studio, per vertex and per pixel (labels: segments; simd {best})",
                         "pbr_speed_vs_accuracy")

# --- 7c. the prefilter: face size and samples per texel, build time against error -------------------
ibl_rows = [r for r in accuracy if r["kind"] == "ibl"]
if ibl_rows:
    fig, ax = plt.subplots(figsize=(8, 5.5))
    sizes = sorted({int(r["method"].split("=")[1]) for r in ibl_rows})
    palette = ["#9467bd", "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e"]
    for size, colour in zip(sizes, palette):
        pts = sorted([r for r in ibl_rows if int(r["method"].split("=")[1]) == size], key=lambda r: int(r["item"].split("=")[1]))
        ax.plot([r["mean_lsb"] for r in pts], [r["ms_per_frame"] for r in pts], color=colour, marker="o",
                label="finest face %d texels%s" % (size, " (the renderer's)" if size == 128 else ""))
        for r in pts:
            ax.annotate(r["item"].split("=")[1], (r["mean_lsb"], r["ms_per_frame"]), textcoords="offset points",
                        xytext=(4, 3), fontsize=7, color=colour)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("mean relative error of the prefiltered cube against the GGX integral (%), roughness 0.2 .. 1")
    ax.set_ylabel("build ms (1024 x 512 picture, 1 thread)")
    ax.set_title("Prefiltering an environment picture (labels: GGX samples per texel)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "ibl_speed_vs_accuracy")
    charts.append("ibl_speed_vs_accuracy")

# --- 7d. skinned normals: the cofactor transform against the plain 3x3, speed against angle ---------
skin_rows = [r for r in accuracy if r["kind"] == "skin"]
if skin_rows:
    fig, ax = plt.subplots(figsize=(8, 5.5))
    methods = sorted({r["method"] for r in skin_rows})
    palette = {"cofactor": "#d62728", "linear": "#1f77b4"}
    for m in methods:
        pts = [r for r in skin_rows if r["method"] == m]
        colour = palette["cofactor" if m.startswith("cofactor") else "linear"]
        marker = "o" if "simd" in m else "s"
        ax.scatter([max(r["mean_lsb"], 1e-7) for r in pts], [r["rate"] / 1e6 for r in pts], color=colour, marker=marker, label=m)
        for k, r in enumerate(sorted(pts, key=lambda r: r["item"])):
            uneven = r["item"].split(":")[1].strip()  # "scale 1 : 1.5 : 0.666667": the joints' uneven scale
            ax.annotate("x" + uneven, (max(r["mean_lsb"], 1e-7), r["rate"] / 1e6), textcoords="offset points",
                        xytext=(5, -10 + 9 * k), fontsize=7, color=colour)
    ax.set_xscale("log")
    ax.set_xlabel("mean angle between skinned normals and the exact inverse transpose (degrees)")
    ax.set_ylabel("M vertices skinned per second (4 influences, 1 thread)")
    ax.set_title("Skinned normals: cofactor matrix against the plain 3x3 (labels: the joints' uneven scale)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "skin_speed_vs_accuracy")
    charts.append("skin_speed_vs_accuracy")

# --- 8. multisampling: edge error against a 64-sample reference, against ms per frame ---------------
msaa_rows = [r for r in accuracy if r["kind"] == "msaa"]
if msaa_rows:
    fig, ax = plt.subplots(figsize=(8, 5.5))
    pts = sorted(msaa_rows, key=lambda r: int(r["method"].split()[0]))
    ax.plot([r["mean_lsb"] for r in pts], [r["ms_per_frame"] for r in pts], color="#1f77b4", marker="o")
    for r in pts:
        if "ms_per_frame_min" in r:
            ax.errorbar([r["mean_lsb"]], [r["ms_per_frame"]],
                        yerr=[[r["ms_per_frame"] - r["ms_per_frame_min"]], [r["ms_per_frame_max"] - r["ms_per_frame"]]],
                        color="#1f77b4", lw=0.7, capsize=2)
        ax.annotate(r["method"], (r["mean_lsb"], r["ms_per_frame"]), textcoords="offset points", xytext=(5, 3),
                    fontsize=8, color="#1f77b4")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("mean error on edge pixels against a 64-sample reference (8-bit steps)")
    ax.set_ylabel("ms per frame (built-in scene, 320x180, 1 thread)")
    ax.set_title(f"Multisampling: samples per pixel (simd {best})")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    save(fig, "msaa_speed_vs_accuracy")
    charts.append("msaa_speed_vs_accuracy")

# --- 9. baking: radiosity's convergence in the white furnace, against time ---------------------------
bake_rows = [r for r in accuracy if r["kind"] == "bake"]
cornell_path = os.path.join(OUT, "cornell_convergence.json")
cornell = json.load(open(cornell_path)) if os.path.exists(cornell_path) else None
if bake_rows:
    fig, axes = plt.subplots(3 if cornell else 2, 1, figsize=(8, 10 if cornell else 7), sharex=True)
    top, bottom = axes[0], axes[1]
    for method, colour in (("1 thread", "#1f77b4"), ("2 threads", "#d62728")):
        pts = sorted([r for r in bake_rows if r["method"] == method], key=lambda r: r["ms_per_frame"])
        if not pts:
            continue
        xs = [r["ms_per_frame"] for r in pts]
        top.plot(xs, [max(r["share"], 1e-6) for r in pts], color=colour, marker="o", label=method)
        bottom.plot(xs, [r["mean_lsb"] for r in pts], color=colour, marker="o", label=method + ", mean")
        bottom.plot(xs, [r["max_lsb"] for r in pts], color=colour, marker="x", ls="--", label=method + ", largest")
        for r in pts if method == "1 thread" else []:  # the same shot counts on both lines: named once
            top.annotate(r["item"].split(", ")[1], (r["ms_per_frame"], max(r["share"], 1e-6)), textcoords="offset points",
                         xytext=(4, 3), fontsize=7, color=colour)
    top.set_yscale("log")
    top.set_ylabel("power still unshot (share of what entered)")
    top.set_title("Radiosity in the white furnace (B = E / (1 - albedo)): convergence against time")
    bottom.set_ylabel("texel error against B (8-bit steps)")
    if cornell:
        third = axes[2]
        for threads, colour in ((1, "#1f77b4"), (2, "#d62728")):
            pts = sorted([r for r in cornell["rows"] if r["threads"] == threads], key=lambda r: r["bake_seconds"])
            if not pts:
                continue
            xs = [1000 * r["bake_seconds"] for r in pts]
            third.plot(xs, [r["mean_abs_steps"] for r in pts], color=colour, marker="o",
                       label=f"{threads} thread{'s' if threads > 1 else ''}")
            for r in pts if threads == 1 else []:
                third.annotate(f"{r['shots']} shots", (1000 * r["bake_seconds"], r["mean_abs_steps"]),
                               textcoords="offset points", xytext=(4, 3), fontsize=7, color=colour)
        third.set_ylabel("mean pixel error (8-bit steps)")
        third.set_title(f"The Cornell box (point light) baked and drawn, {cornell['size']}x{cornell['size']}, against "
                        f"Embree's path tracer ({cornell['spp']} paths a pixel)", fontsize=10)
    axes[-1].set_xscale("log")
    axes[-1].set_xlabel("bake time (ms)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "bake_convergence")
    charts.append("bake_convergence")

# --- summary -----------------------------------------------------------------------------------------
ctx = lighting["context"]
points_rate = {}  # (method, threads) -> row, for 4 point lights on 64 Ki vertices
for b in bench_rows(lighting):
    parts = b["name"].split("/")
    if parts[2] == "point" and parts[3] == "lights:4" and parts[4] == "vertices:65536":
        threads = parts[5].replace("threads:", "") if len(parts) > 5 and parts[5].startswith("threads:") else "1"
        points_rate[(parts[1], threads)] = b
lines = [f"Measured {time.strftime('%Y-%m-%d')} on {ctx.get('host_name', platform.node())} "
         f"({ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz); roofline: read "
         f"{float(ctx['roofline_read_GB/s']):.1f} GB/s, triad {float(ctx['roofline_triad_GB/s']):.1f} GB/s, "
         f"peak {float(ctx['roofline_peak_GFLOP/s']):.1f} GFLOP/s (1 thread). Each figure is the median of "
         f"{max((r.get('_runs', 1) for r in bench_rows(frames)), default=1)} runs (`tools/charts`).", "",
         "| figure | value | share of the machine's limit |", "|---|---|---|"]
for m in order:
    b = next((x for x in bench_rows(lighting) if x["name"] == f"BM_Lighting/{m}/mixed/lights:4/vertices:4096"), None)
    if b:
        lines.append(f"| vertex-lights/s, {m.replace('_', ' ')}, 4 mixed lights, 1 thread | {b['vertex_lights/s'] / 1e6:.1f} M "
                     f"| {100 * b['bw_share']:.1f} % of triad bandwidth |")
for (m, threads), b in sorted(points_rate.items()):
    lines.append(f"| vertex-lights/s, {m.replace('_', ' ')}, 4 point lights, 64 Ki vertices, {threads} thread"
                 f"{'s' if threads != '1' else ''} | {b['vertex_lights/s'] / 1e6:.1f} M "
                 f"| {100 * b.get('flop_share', 0):.1f} % of peak FMA (counted flops, the threads' peak) |")
for (v, t), rate in sorted(fill.items()):
    b = next(x for x in bench_rows(frames) if x["name"].startswith(f"BM_Fill/{v}/gouraud/{t}"))
    lines.append(f"| pixels filled/s, {v}, {t.replace(':', ' ')} | {rate / 1e9:.2f} G | {100 * b['bw_share']:.1f} % of triad bandwidth (image writes) |")
for b in bench_rows(frames):
    if b["name"].startswith(f"BM_Frame/{best}/bunny/1920x1080/"):
        lines.append(f"| Stanford bunny 1080p, {best}, {b['name'].split('/')[4].replace(':', ' ')} | {b['real_time']:.2f} ms | |")
phong = [r for r in accuracy if r["kind"] == "image" and r["method"] == "phong"]
if phong:
    finest = max(phong, key=lambda r: int(r["item"].split("=")[1]))
    lines.append(f"| Phong PSNR vs ray-cast spheres, {finest['item']} | {finest['psnr_db']:.1f} dB | target >= 45 dB |")
shadow_frames = {}  # (scene, threads) -> {method: ms per frame}
for b in bench_rows(frames):
    parts = b["name"].split("/")
    if parts[0] == "BM_Shadow":
        shadow_frames.setdefault((parts[2], parts[4]), {})[parts[1]] = b
if shadow_frames:
    lines += ["", "Shadows, 1920x1080, Phong, the first light shadowed (BM_Shadow; share: the method's part of its frame):", "",
              "| scene, threads | no shadows | map (ms, share, of which map passes) | volume (ms, share, of which depth pass and volumes) | ray-cast (ms, share, of which hierarchy) |",
              "|---|---|---|---|---|"]
    for (scene, threads), m in sorted(shadow_frames.items()):
        if "none" not in m:
            continue
        none = m["none"]["real_time"]
        cells = []
        for method in ("map", "volume", "raycast"):
            if method in m:
                t = m[method]["real_time"]
                cells.append(f"{t:.1f} ms, {100 * (t - none) / t:.0f} %, {m[method].get('shadows_ms', 0):.1f} ms")
            else:
                cells.append("")
        lines.append(f"| {scene}, {threads.replace('threads:', '')} | {none:.1f} ms | {cells[0]} | {cells[1]} | {cells[2]} |")
with open(os.path.join(OUT, "summary.md"), "w") as f:
    f.write("\n".join(lines) + "\n")
print("\n".join(lines))
print("charts:", ", ".join(os.path.join(OUT, n + ".png") for n in charts))
