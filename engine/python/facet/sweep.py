"""Sweeps: many independent facet jobs on a Dask cluster (a local one by default).

A sweep is a list of jobs, each one `facet` command: the frames of a turntable (one job a frame,
`facet render MODEL --frames N --frame-range k:k+1`, so each image has the bytes of the same frame
rendered in one run) or the points of a parameter grid (`facet render MODEL --json --seconds S`
for every combination of --grid values). Results are gathered into DIR/summary.json and
DIR/summary.csv, one row per job with its status, attempts, worker, wall time and the context
facet reported. A job whose command fails is retried (--retries); a job whose worker dies is run
again on another worker by Dask: no job is lost.

    python3 -m facet.sweep MODEL --frames 36 --workers 2 -o DIR --width 640 --height 360
    python3 -m facet.sweep MODEL --grid pow=auto,exact --grid threads=1,2 --seconds 0.5 -o DIR
    python3 -m facet.sweep MODEL --frames 36 -o DIR -- --exposure -2 --clear 0.2,0.2,0.2

The common render options (--width, --height, --shading, --msaa, --path, --isa, --pow, --view,
--up, --fov, --projection, --camera, --exposure, --tone-mapping, --allow-path) are taken as they
are; any other facet render option goes after `--`. A facet command that refuses its options or
its input (exit status 2) is not retried: the sweep stops and prints facet's message.
    python3 -m facet.sweep MODEL --frames 36 --scheduler tcp://host:8786 -o DIR   # an existing cluster

Without Dask (or for a Slurm job array, one task each), `facet render MODEL --frames 36
--frame-range A:B -o DIR/turn.png` draws part of the same turntable: docs/python.md.
"""
import argparse
import ctypes
import csv
import itertools
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time


def find_facet():
    """The facet program beside this package: the build tree's build/bin/facet, an install
    prefix's bin/facet, or the first on PATH."""
    here = os.path.dirname(os.path.abspath(__file__))
    for candidate in (os.path.join(here, "..", "..", "bin", "facet"),  # build/python/facet -> build/bin
                      os.path.join(here, "..", "..", "..", "..", "bin", "facet")):  # prefix/lib/python3/dist-packages/facet
        if os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return os.path.normpath(candidate)
    found = shutil.which("facet")
    if not found:
        raise SystemExit("facet.sweep: cannot find the facet program (give --facet PATH)")
    return found


def _die_with_parent():
    """In the child, before exec: killed when the worker that started it dies (Linux), so that a
    cancelled or timed-out sweep leaves no facet running."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def run_job(job):
    """Runs one job on a worker: its facet command; returns its row. Raises on failure, so that
    Dask retries it. job["deadline"]: the sweep's time limit (time.time() seconds), after which
    the command is killed. job["kill_once"]: a marker path; when it does not exist yet, the worker
    creates it and dies mid-job (fault injection, to show that a lost worker loses nothing)."""
    started = time.time()
    deadline = job.get("deadline")
    if deadline is not None and started >= deadline:
        raise RuntimeError("job %s: the sweep's time limit ran out before it started" % job["key"])
    marker = job.get("kill_once")
    if marker and not os.path.exists(marker):
        with open(marker, "w") as f:
            f.write("%d\n" % os.getpid())
        os.kill(os.getpid(), signal.SIGKILL)
    try:
        result = subprocess.run(job["command"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                preexec_fn=_die_with_parent,
                                timeout=None if deadline is None else max(0.01, deadline - time.time()))
    except subprocess.TimeoutExpired:
        raise RuntimeError("job %s: stopped at the sweep's time limit" % job["key"]) from None
    if result.returncode == 2:
        # Refused (a usage error, a file it cannot read): running it again cannot help. Reported,
        # not raised, so that Dask does not retry it.
        return {"key": job["key"], "status": "refused", "host": socket.gethostname(), "pid": os.getpid(),
                "seconds": time.time() - started, "error": result.stderr.strip()}
    if result.returncode != 0:
        raise RuntimeError("job %s: %s exited %d: %s" % (job["key"], job["command"][0], result.returncode, result.stderr.strip()))
    record = None
    for line in result.stdout.splitlines():
        line = line.strip()
        if line.startswith("{"):
            try:
                record = json.loads(line)  # the last JSON line: a turntable's summary, or the frame's record
            except ValueError:
                pass
    return {"key": job["key"], "status": "ok", "host": socket.gethostname(), "pid": os.getpid(),
            "seconds": time.time() - started, "record": record}


# facet render's options a sweep takes as its own and passes to every job (the rest after `--`).
PASSED_ON = ("width", "height", "shading", "msaa", "path", "isa", "pow", "view", "up", "fov", "projection", "camera",
             "exposure", "tone-mapping", "allow-path")


def make_jobs(args, facet_bin, extra):
    jobs = []
    common = [facet_bin, "render", args.model] if args.model else [facet_bin, "render"]
    for option in PASSED_ON:
        value = getattr(args, option.replace("-", "_"))
        for v in value if isinstance(value, list) else ([] if value is None else [value]):
            extra = ["--%s=%s" % (option, v)] + extra  # with "=": a value such as -z is not taken for an option
    if args.frames:
        out = os.path.join(args.output, args.name)
        for k in range(args.frames):
            jobs.append({"key": "frame-%04d" % k,
                         "command": common + ["--frames", str(args.frames), "--frame-range", "%d:%d" % (k, k + 1),
                                              "-o", out, "--json"] + extra})
    else:
        axes = []
        for spec in args.grid:
            name, _, values = spec.partition("=")
            if not name or not values:
                raise SystemExit("facet.sweep: --grid expects NAME=V1,V2,... (a facet render option without --), found %r" % spec)
            axes.append([(name, v) for v in values.split(",")])
        for point in itertools.product(*axes):
            options = []
            for name, value in point:
                options += ["--" + name, value]
            key = ",".join("%s=%s" % nv for nv in point) or "default"
            jobs.append({"key": key, "command": common + ["-o", os.path.join(args.output, "point.png"), "--json",
                                                          "--seconds", str(args.seconds)] + options + extra})
    return jobs


def run(jobs, client, retries=2, deadline=None):
    """Submits every job to `client` (a distributed.Client) and gathers their rows in job order;
    a job that still fails after its retries gets a row with status "failed" and the error. A job
    facet refused (exit status 2) stops the sweep: the jobs not done are cancelled ("refused"
    rows say why). With a deadline (time.time() seconds), jobs not finished by then are cancelled
    and reported so."""
    from distributed import wait

    for job in jobs:
        job["deadline"] = deadline
    futures = {client.submit(run_job, job, key="facet-" + job["key"] + "-" + str(time.time_ns()), retries=retries, pure=False): job
               for job in jobs}
    refused = None
    seen = set()  # futures finished and looked at
    end = None if deadline is None else deadline + 1.0  # a second past the deadline: the jobs themselves stop at it
    while refused is None:
        # Asked again each round: a future whose worker died goes back to pending when Dask runs
        # its job again elsewhere, even after wait() has returned it (a lost worker must not
        # make its jobs look finished, or cancelled at a time limit the sweep does not have).
        pending = [f for f in futures if not f.done()]
        for future in futures:
            if future.done() and future not in seen:
                seen.add(future)
                if future.status == "finished" and future.result().get("status") == "refused":
                    refused = future.result()
                    break
        if not pending or refused is not None:
            break
        remaining = None if end is None else end - time.time()
        if remaining is not None and remaining <= 0:
            break
        try:
            wait(pending, timeout=1.0 if remaining is None else min(1.0, remaining), return_when="FIRST_COMPLETED")
        except TimeoutError:
            pass
    rows = {}
    for future, job in futures.items():
        if not future.done():
            future.cancel()
            why = "cancelled: job %s was refused" % refused["key"] if refused else "cancelled at the sweep's time limit"
            row = {"key": job["key"], "status": "failed", "error": why}
        else:
            try:
                row = future.result()
            except Exception as e:  # noqa: BLE001 - every failure is reported in the summary
                row = {"key": job["key"], "status": "failed", "error": str(e)}
        row["command"] = job["command"]
        rows[job["key"]] = row
    return [rows[job["key"]] for job in jobs]


def write_summary(rows, output, wall_seconds, workers):
    os.makedirs(output, exist_ok=True)
    ok = sum(1 for r in rows if r["status"] == "ok")
    summary = {"jobs": len(rows), "ok": ok, "failed": len(rows) - ok, "wall_seconds": wall_seconds,
               "jobs_per_second": len(rows) / wall_seconds if wall_seconds > 0 else None, "workers": workers, "rows": rows}
    with open(os.path.join(output, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    with open(os.path.join(output, "summary.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["key", "status", "host", "pid", "seconds", "frame_seconds_median", "facet_version", "commit", "isa", "error"])
        for r in rows:
            rec = r.get("record") or {}
            ctx = rec.get("context", {})
            fs = rec.get("frame_seconds", {})
            w.writerow([r["key"], r["status"], r.get("host", ""), r.get("pid", ""), "%.6f" % r["seconds"] if "seconds" in r else "",
                        fs.get("median", ""), ctx.get("facet_version", ""), ctx.get("commit", ""), ctx.get("isa", ""), r.get("error", "")])
    return summary


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m facet.sweep", description=__doc__.split("\n\n")[0])
    p.add_argument("model", nargs="?", help="scene file or model (default: the built-in scene)")
    p.add_argument("-o", "--output", required=True, help="folder for the images and summary.json / summary.csv")
    p.add_argument("--frames", type=int, help="a turntable of N frames, one job each")
    p.add_argument("--name", default="turn.png", help="the turntable's image name (default turn.png: turn_0000.png, ...)")
    p.add_argument("--grid", action="append", default=[], help="NAME=V1,V2,...: a facet render option and its values (repeatable)")
    p.add_argument("--seconds", type=float, default=0.5, help="grid points: render for at least this long (default 0.5)")
    p.add_argument("--workers", type=int, default=2, help="local cluster: worker processes (default 2)")
    p.add_argument("--threads-per-worker", type=int, default=1)
    p.add_argument("--scheduler", help="address of a running Dask scheduler instead of a local cluster")
    p.add_argument("--retries", type=int, default=2, help="times a failed job is run again (default 2)")
    p.add_argument("--facet", help="the facet program (default: beside this package, else on PATH)")
    p.add_argument("--time-limit", type=float, help="stop the whole sweep after S seconds: running jobs are killed, "
                   "the rest cancelled, each reported as failed (default: no limit)")
    for option in PASSED_ON:
        p.add_argument("--" + option, action="append" if option == "allow-path" else None,
                       help="passed to every facet render command" if option == "width" else argparse.SUPPRESS)
    p.add_argument("--kill-worker-once-at", help=argparse.SUPPRESS)  # fault injection: the job key whose worker dies once
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = []
    if "--" in argv:  # what follows goes to every facet command as it is
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    args = p.parse_args(argv)
    if (args.frames is not None) == bool(args.grid):
        p.error("give --frames N (a turntable) or --grid NAME=VALUES (a parameter grid)")
    if args.frames is not None and args.frames < 1:
        p.error("--frames: expected a number of frames >= 1, found %d" % args.frames)
    if args.workers < 1:
        p.error("--workers: expected 1 or more worker processes, found %d" % args.workers)
    if args.threads_per_worker < 1:
        p.error("--threads-per-worker: expected 1 or more, found %d" % args.threads_per_worker)
    if args.retries < 0:
        p.error("--retries: expected 0 or more, found %d" % args.retries)
    if not args.seconds > 0 or args.seconds > 1e9:
        p.error("--seconds: expected a number of seconds > 0, found %r" % args.seconds)
    if args.time_limit is not None and not (args.time_limit > 0 and args.time_limit < 1e9):
        p.error("--time-limit: expected a number of seconds > 0, found %r" % args.time_limit)
    # The turntable's images land in the output folder itself: a plain file name, nothing that
    # climbs out of it or names another folder.
    if (os.path.basename(args.name) != args.name or args.name in ("", ".", "..")
            or any(ord(c) < 0x20 or ord(c) == 0x7f for c in args.name)):
        p.error("--name: expected a file name without a folder (turn.png), found %r" % args.name)
    facet_bin = os.path.abspath(args.facet) if args.facet else find_facet()
    os.makedirs(args.output, exist_ok=True)  # the jobs write into it: a grid's as a turntable's
    jobs = make_jobs(args, facet_bin, extra)
    if args.kill_worker_once_at:
        for job in jobs:
            if job["key"] == args.kill_worker_once_at:
                job["kill_once"] = os.path.join(os.path.abspath(args.output), ".killed-" + job["key"])

    from distributed import Client, LocalCluster

    started = time.time()
    if args.scheduler:
        client = Client(args.scheduler)
        cluster = None
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=args.threads_per_worker, processes=True,
                               dashboard_address=None, silence_logs=50)
        client = Client(cluster)
    try:
        rows = run(jobs, client, retries=args.retries,
                   deadline=None if args.time_limit is None else started + args.time_limit)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    summary = write_summary(rows, args.output, time.time() - started, args.workers if not args.scheduler else None)
    refused = [r for r in rows if r["status"] == "refused"]
    if refused:
        sys.stderr.write("facet.sweep: job %s was refused, the sweep stopped:\n%s\n" % (refused[0]["key"], refused[0]["error"]))
        return 2
    print("facet.sweep: %d jobs, %d ok, %d failed in %.2f s (%.2f jobs/s); %s" %
          (summary["jobs"], summary["ok"], summary["failed"], summary["wall_seconds"], summary["jobs_per_second"] or 0,
           os.path.join(args.output, "summary.json")))
    return 0 if summary["failed"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
