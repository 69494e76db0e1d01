"""One timed run of a command, shared by the benchmark scripts (ratios.py, scaling.py)."""

import subprocess
import sys
import time


def run(cmd, cwd=None):
    """Wall seconds, CPU seconds (user + system) and peak RSS (MB) of one run of `cmd`,
    measured by GNU time (/usr/bin/time): the resource usage of a child of this process
    would count the memory it inherited from Python before its exec. A failing command
    ends the script with its error output."""
    start = time.perf_counter()
    proc = subprocess.run(["/usr/bin/time", "-f", "%U %S %M", *cmd], cwd=cwd,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed: {proc.stderr[-2000:]}")
    user, system, rss_kb = proc.stderr.strip().splitlines()[-1].split()
    return wall, float(user) + float(system), float(rss_kb) / 1024
