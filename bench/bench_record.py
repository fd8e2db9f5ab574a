"""What every benchmark script records with its figures: the machine, the
environment MPI runs need here, and the report written where asked."""
import os
import platform
from datetime import datetime, timezone
from pathlib import Path


def cpu_model():
    """The CPU's model name, from /proc/cpuinfo."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def mpi_env(threads=1):
    """The environment for mpiexec: one OpenMP thread per rank unless asked,
    and Open MPI allowed to run as root (CI and containers are root)."""
    return dict(os.environ, OMP_NUM_THREADS=str(threads), OMPI_ALLOW_RUN_AS_ROOT="1",
                OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def write_report(lines, out):
    """The report's lines to `out`, or to stdout for "-"."""
    text = "\n".join(lines) + "\n"
    if out == "-":
        print(text)
        return
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    Path(out).write_text(text)


def machine_lines():
    """The date, machine and GPU lines that head a CPU benchmark's report."""
    return [
        f"- date: {datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}",
        f"- machine: {cpu_model()}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()}",
        "- GPU: none used (CPU backend)",
    ]
