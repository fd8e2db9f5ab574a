"""What every benchmark script records with its figures: the machine, the
environment MPI runs need here, and the report written where asked."""
import os
import platform
import subprocess
import sys
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


def sample_list(values):
    """A report's samples column: every value to 0.1."""
    return ", ".join(f"{x:.1f}" for x in values)


def run_command(cmd, root, env=None):
    """Runs `cmd`; its stdout and stderr together, and the command as a report
    records it (paths relative to `root`, so no machine's paths). Exits with
    the command and its output when it fails."""
    done = subprocess.run([str(c) for c in cmd], env=env, capture_output=True, text=True)
    shown = " ".join(str(c) for c in cmd).replace(f"{root}/", "")
    if done.returncode != 0:
        sys.exit(f"failed: {shown}\n{done.stdout}\n{done.stderr}")
    return done.stdout + done.stderr, shown
