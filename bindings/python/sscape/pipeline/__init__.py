"""Scan collections on a Dask cluster: register_collection and bootstrap do what `sscape register`
and `sscape bootstrap` do, one task per scan, on a LocalCluster of this machine by default or on
any Dask cluster (client= or scheduler=) whose workers see the same files. Needs Debian's
python3-distributed and libsscape_offline (the package built from a full build has it).

    from sscape import pipeline
    pipeline.register_collection("scans/", out_dir="registered/")            # LocalCluster
    pipeline.bootstrap("scans/", rounds=3, out_dir="learned/", scheduler="tcp://head:8786")

Command line: python3 -m sscape.pipeline register|bootstrap ... (--help).
"""
from .bootstrap import Bootstrapping, bootstrap
from .register import register_collection
from .scans import Scan, list_scans

__all__ = ["Bootstrapping", "Scan", "bootstrap", "list_scans", "register_collection"]
