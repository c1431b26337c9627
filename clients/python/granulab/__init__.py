"""granulab: the Python package of the granulab lab server (granulabd). Standard library only at its core.

    import granulab
    client = granulab.Client()                   # GRANULAB_SERVER, GRANULAB_TOKEN, GRANULAB_CA_FILE
    job = client.submit({"experiment": "two_cube_sliding"})
    status = job.wait()                          # a progress display; the final status dict
    jobs = [client.submit(s) for s in specs]     # Futures: concurrent.futures.as_completed(jobs) works
    granulab.wait(jobs)                          # one display for them all
    sweep = client.submit_sweep(spec, {"loading.confining_pressure": [10e3, 30e3]})
    sweep.wait(); sweep.frame(); sweep.curves()  # pandas DataFrames: a row per job; every curve, stacked
    job.frame(units="natural"), job.snapshot_frame(1), job.curve_svg()

Install: `pip install ./clients/python` (offline: the build backend is in the package's folder and needs nothing).
"""

from granulab.client import DEFAULT_SERVER, TERMINAL, Client, GranulabError
from granulab.headline import KeyValue, key_values
from granulab.jobs import Job, JobFailed
from granulab.pictures import Picture
from granulab.progress import wait
from granulab.sweeps import Sweep

__version__ = "0.1.0"

__all__ = ["Client", "GranulabError", "Job", "JobFailed", "KeyValue", "key_values", "Picture", "Sweep", "wait",
           "DEFAULT_SERVER", "TERMINAL", "__version__"]
