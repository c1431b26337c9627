"""granulab: the Python package of the granulab lab server (granulabd). Standard library only at its core.

    import granulab
    client = granulab.Client()                   # GRANULAB_SERVER, GRANULAB_TOKEN, GRANULAB_CA_FILE
    job = client.submit({"experiment": "two_cube_sliding"})
    status = job.wait()                          # a progress display; the final status dict
    jobs = [client.submit(s) for s in specs]     # Futures: concurrent.futures.as_completed(jobs) works
    granulab.wait(jobs)                          # one display for them all

Install: `pip install ./clients/python` (offline: the build backend is in the package's folder and needs nothing).
"""

from granulab.client import DEFAULT_SERVER, TERMINAL, Client, GranulabError
from granulab.headline import KeyValue, key_values
from granulab.jobs import Job, JobFailed
from granulab.progress import wait

__version__ = "0.1.0"

__all__ = ["Client", "GranulabError", "Job", "JobFailed", "KeyValue", "key_values", "wait", "DEFAULT_SERVER",
           "TERMINAL", "__version__"]
