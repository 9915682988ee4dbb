"""Job-seconds per rule of one Snakemake run, read from its log (.snakemake/log/*.log).

    python benchmarks/job_seconds.py [LOG]        # default: the newest log under .snakemake/log

Each job's time runs from the timestamp printed above its `rule`/`localrule` block to the one
above its `Finished jobid:` line (1-second resolution, so a rule of many short jobs is known to
about +-1 s per job).  Prints, per rule, the jobs, the job-seconds and the mean per job, then
the total and the wall time from the first job's start to the last job's end.  Jobs started
but never finished (a killed run) are listed apart.
"""

import re
import sys
from datetime import datetime
from pathlib import Path

STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ \d\d:\d\d:\d\d \d{4})\]$")
START = re.compile(r"^(?:local)?rule (\w+):$")
JOBID = re.compile(r"^\s+jobid: (\d+)$")
FINISHED = re.compile(r"^Finished jobid: (\d+) \(Rule: (\w+)\)$")


def job_times(lines):
    """({jobid: (rule, start, end)}, {jobid: (rule, start)} unfinished) from a log's lines."""
    stamp = None
    started, pending_rule, done = {}, None, {}
    for line in lines:
        m = STAMP.match(line)
        if m:
            stamp = datetime.strptime(m.group(1), "%a %b %d %H:%M:%S %Y")
            continue
        m = START.match(line)
        if m:
            pending_rule = (m.group(1), stamp)
            continue
        m = JOBID.match(line)
        if m and pending_rule is not None:
            started[int(m.group(1))] = pending_rule
            pending_rule = None
            continue
        m = FINISHED.match(line)
        if m:
            jobid = int(m.group(1))
            rule, start = started.pop(jobid)
            done[jobid] = (rule, start, stamp)
    return done, started


def report(done, unfinished):
    rules = {}
    for rule, start, end in done.values():
        n, s = rules.get(rule, (0, 0.0))
        rules[rule] = (n + 1, s + (end - start).total_seconds())
    lines = [f"{'rule':24s} {'jobs':>5s} {'job-s':>8s} {'s/job':>7s}"]
    for rule, (n, s) in sorted(rules.items(), key=lambda kv: -kv[1][1]):
        lines.append(f"{rule:24s} {n:5d} {s:8.0f} {s / n:7.1f}")
    total = sum(s for _, s in rules.values())
    jobs = sum(n for n, _ in rules.values())
    lines.append(f"{'total':24s} {jobs:5d} {total:8.0f}")
    if done:
        first = min(start for _, start, _ in done.values())
        last = max(end for _, _, end in done.values())
        wall = (last - first).total_seconds()
        lines.append(f"wall {int(wall // 60)} min {int(wall % 60)} s (first job start to last end)")
    for jobid, (rule, start) in sorted(unfinished.items()):
        lines.append(f"unfinished: job {jobid} ({rule}) started {start:%H:%M:%S}")
    return "\n".join(lines)


def main(argv):
    if len(argv) > 1:
        log = Path(argv[1])
    else:
        logs = sorted(Path(".snakemake/log").glob("*.log"), key=lambda p: p.stat().st_mtime)
        if not logs:
            sys.exit("job_seconds: no log under .snakemake/log (give the log's path)")
        log = logs[-1]
    if not log.is_file():
        sys.exit(f"job_seconds: {log}: no such file")
    done, unfinished = job_times(log.read_text().splitlines())
    print(f"# {log}")
    print(report(done, unfinished))


if __name__ == "__main__":
    main(sys.argv)
