"""The runs TAG_KIND_1 .. TAG_KIND_R of a benchmark, measured by /usr/bin/time -v (bench_common.sh,
`timed`): the median wall time [s], the median peak resident memory [MiB] and the number of the
run with the median wall time."""
import re
import statistics


def measure(tag, kind, repeat):
    walls, mems = [], []
    for r in range(1, repeat + 1):
        t = open(f"{tag}_{kind}_{r}.time").read()
        m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", t)
        h = int(m.group(1) or 0)
        walls.append(h * 3600 + int(m.group(2)) * 60 + float(m.group(3)))
        mems.append(int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024)
    median_run = sorted(range(repeat), key=lambda i: walls[i])[(repeat - 1) // 2] + 1
    return statistics.median(walls), statistics.median(mems), median_run
