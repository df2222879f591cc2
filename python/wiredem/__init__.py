"""wiredem for Python: the REST API and the result files as numpy and pandas objects.

    import wiredem
    client = wiredem.Client("http://127.0.0.1:8080")
    job = client.submit("examples/tiny.json")
    client.wait(job["id"])
    result = client.result(job["id"], "tiny")          # fetches summary.json and result.h5
    curves = result.stress_ratio_curves()              # {σ₃ [Pa]: DataFrame}
    result.mohr_coulomb                                # φ, c, R² as the engine fitted them

docs/python.md is the guide; docs/api.md and docs/results.md the contracts it follows.
"""
from .client import FINAL_STATES, ROUTES, Client, Route
from .errors import (ApiError, JobCancelled, JobFailed, NetworkError, ResultError, StudyFailed, WaitTimeout,
                     WiredemError)
from .results import LOADING, FreeStanding, MohrCoulomb, Result, Snapshot, Specimen, Test, find_wiredem, open_result
from .spec import with_fields
from .study import Study, open_study

#: Opens a result.h5 or a folder holding one (with its summary.json): :func:`wiredem.results.open_result`.
open = open_result  # noqa: A001 - wiredem.open("result.h5") is the package's door to a file

__version__ = "0.1.0"

__all__ = ["Client", "Route", "ROUTES", "FINAL_STATES", "open", "open_result", "open_study", "Result", "Test",
           "FreeStanding",
           "Snapshot", "Specimen", "MohrCoulomb", "Study", "LOADING", "with_fields", "find_wiredem", "WiredemError", "ApiError",
           "NetworkError", "JobFailed", "JobCancelled", "StudyFailed", "WaitTimeout", "ResultError", "__version__"]
