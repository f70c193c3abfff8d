"""Scan collections on a Dask cluster: register_collection, bootstrap, fit_collection and
measure_collection do what `sscape register`, `sscape bootstrap`, `sscape fit` and `sscape
measure` do, one task per scan, on a LocalCluster of this machine by default or on
any Dask cluster (client= or scheduler=) whose workers see the same files. Needs Debian's
python3-distributed and libsscape_offline (the package built from a full build has it).

    from sscape import pipeline
    pipeline.register_collection("scans/", out_dir="registered/")            # LocalCluster
    pipeline.bootstrap("scans/", rounds=3, out_dir="learned/", scheduler="tcp://head:8786")

Command line: python3 -m sscape.pipeline register|bootstrap ... (--help).
"""
from .bootstrap import Bootstrapping, bootstrap
from .fit import fit_collection, measure_collection
from .register import register_collection
from .scans import Scan, list_scans

__all__ = ["Bootstrapping", "Scan", "bootstrap", "fit_collection", "list_scans", "measure_collection", "register_collection"]
