"""Memory of this process and of the machine, the one place each is read: the peak resident
size (``ru_maxrss``, which Linux reports in kB) and ``MemAvailable`` of /proc/meminfo."""

from __future__ import annotations

import resource
from pathlib import Path


def peak_rss_mb() -> float:
    """Peak resident memory of this process (MB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def mem_available_gb() -> float:
    """MemAvailable of /proc/meminfo (GB): what a new run can take without swapping."""
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemAvailable:"):
            return int(line.split()[1]) / 1024.0**2
    return float("nan")


__all__ = ["mem_available_gb", "peak_rss_mb"]
