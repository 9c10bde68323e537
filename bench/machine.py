"""The machine a benchmark ran on, for the Python benchmark scripts' reports."""
import os
import platform


def machine():
    """CPU model, cores, OMP_NUM_THREADS, the 1-minute load average and the platform."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    try:
        load = round(os.getloadavg()[0], 2)
    except OSError:
        load = None
    return {"cpu": cpu, "cores": os.cpu_count(), "omp_num_threads": os.environ.get("OMP_NUM_THREADS"),
            "load_average_1min": load, "platform": platform.platform(), "python": platform.python_version()}
