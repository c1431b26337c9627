#!/usr/bin/env python3
"""The one-file import path of earlier versions, kept working: `from granulab_client import Client` with
clients/python on sys.path gives the package's client (clients/python/granulab) as it was: submit() returns the new
job's id and submit_sweep() the pair (sweep id, [job ids]), where the package's return a Job (a Future) and a Sweep.
New code: `import granulab` after `pip install ./clients/python`. As a script: the package's command line."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import granulab  # noqa: E402
from granulab.client import DEFAULT_SERVER, GranulabError  # noqa: E402,F401
from granulab.headline import KeyValue, key_values  # noqa: E402,F401

__all__ = ["Client", "GranulabError", "DEFAULT_SERVER", "KeyValue", "key_values"]


class Client(granulab.Client):
    def submit(self, spec, reuse=False, priority=None):
        """Submit a spec (a dict, a JSON string, or a path to a JSON file). Returns the job id."""
        return self.submit_id(spec, reuse=reuse, priority=priority)

    def submit_sweep(self, spec, vary, mode="product", label="", priority=None):
        """A sweep of `spec` over `vary` ({"dotted.key": [values]}); returns (sweep id, [job ids])."""
        return self.submit_sweep_ids(spec, vary, mode=mode, label=label, priority=priority)


if __name__ == "__main__":
    from granulab.cli import main

    sys.exit(main(prog="granulab_client.py"))
