"""A client of the wiredem HTTP API (docs/api.md), on the standard library's urllib.

Every request goes through one table of the routes the client uses,
:data:`ROUTES`: each operation's method, path template, and the query
parameters and headers it may send. ``python/tests/test_server.py`` holds that
table to the server's own OpenAPI document (``GET /v1/openapi.json``): every
route and method exists there with every parameter the client sends, under the
same operationId.

It does what the ``wiredem`` command does (client/commands.cpp, docs/client.md):
a fresh ``Idempotency-Key`` per submit and retries of a lost reply, waiting
through a restarting server, and resumable downloads of ``result.h5``
(``Range`` + ``If-Range`` with the result's ETag, kept beside the part file).
"""
from __future__ import annotations

import json
import os
import secrets
import time
import urllib.error
import urllib.parse
import urllib.request
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

from .errors import ApiError, JobCancelled, JobFailed, NetworkError, StudyFailed, WaitTimeout, WiredemError

if TYPE_CHECKING:  # names for the annotations only
    import pandas

    from .results import Result
    from .study import Study

JSON = Dict[str, Any]
#: A job spec or study: a dict, or the path of a JSON file holding one.
SpecLike = Union[Mapping[str, Any], str, "os.PathLike[str]"]

#: The job states that are final (docs/api.md, ``GET /v1/jobs/{id}``).
FINAL_STATES = ("succeeded", "failed", "cancelled")


@dataclass(frozen=True)
class Route:
    """One operation of the API the client calls."""

    method: str                       #: GET, POST, DELETE, HEAD
    path: str                         #: template, e.g. ``/v1/jobs/{id}``
    query: Tuple[str, ...] = ()       #: query parameters it may send
    headers: Tuple[str, ...] = ()     #: request headers it may send besides Authorization and Content-Type
    operation_id: str = ""            #: the OpenAPI operationId (a HEAD's: the GET's + "Head")


def _r(op: str, method: str, path: str, query: Sequence[str] = (), headers: Sequence[str] = ()) -> Tuple[str, Route]:
    return op, Route(method, path, tuple(query), tuple(headers), op)


#: Every request the client makes, by a name; the OpenAPI test checks each.
ROUTES: Dict[str, Route] = dict([
    _r("getHealth", "GET", "/v1/health"),
    _r("getOpenApi", "GET", "/v1/openapi.json"),
    _r("getJobSpecSchema", "GET", "/v1/job-spec/schema"),
    _r("submitJob", "POST", "/v1/jobs", headers=("Idempotency-Key",)),
    _r("listJobs", "GET", "/v1/jobs", query=("state", "limit", "cursor")),
    _r("getJob", "GET", "/v1/jobs/{id}"),
    _r("deleteJob", "DELETE", "/v1/jobs/{id}", query=("remove",)),
    _r("getJobSummary", "GET", "/v1/jobs/{id}/summary"),
    _r("getJobResult", "GET", "/v1/jobs/{id}/result.h5", headers=("Range", "If-Range")),
    _r("getJobResultHead", "HEAD", "/v1/jobs/{id}/result.h5"),
    _r("getJobTests", "GET", "/v1/jobs/{id}/tests"),
    _r("getJobTestsTestSeries", "GET", "/v1/jobs/{id}/tests/{test}/series", query=("max_points", "columns")),
    _r("getJobTestsTestSnapshotsKWireAutocorrelation", "GET",
       "/v1/jobs/{id}/tests/{test}/snapshots/{k}/wire_autocorrelation"),
    _r("submitStudy", "POST", "/v1/studies"),
    _r("listStudies", "GET", "/v1/studies", query=("limit", "cursor")),
    _r("getStudy", "GET", "/v1/studies/{id}"),
    _r("deleteStudy", "DELETE", "/v1/studies/{id}", query=("remove",)),
    _r("getStudySummary", "GET", "/v1/studies/{id}/summary"),
])


# Straight to the server, as the wiredem command goes: no proxy from the environment
# (http_proxy would send loopback requests elsewhere) and no redirects followed.
class _NoRedirect(urllib.request.HTTPRedirectHandler):
    def redirect_request(self, *args: Any, **kwargs: Any) -> None:
        return None


_OPENER = urllib.request.build_opener(urllib.request.ProxyHandler({}), _NoRedirect())


class _Reply:
    """An HTTP reply: status, headers (lower-case names), body bytes."""

    def __init__(self, status: int, headers: Mapping[str, str], body: bytes) -> None:
        self.status = status
        self.headers = {k.lower(): v for k, v in headers.items()}
        self.body = body

    def json(self) -> Any:
        return json.loads(self.body.decode("utf-8"))


def _load_document(doc: SpecLike) -> bytes:
    """A job spec or study as JSON bytes: a mapping is serialised, a path read."""
    if isinstance(doc, Mapping):
        return json.dumps(doc).encode("utf-8")
    path = Path(os.fspath(doc))
    try:
        text = path.read_bytes()
    except OSError as e:
        raise WiredemError(f"cannot read {path}: {e.strerror}") from e
    try:
        json.loads(text.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as e:
        raise WiredemError(f"{path} is not JSON: {e}") from e
    return text


def _retry_after(headers: Mapping[str, str]) -> Optional[float]:
    value = headers.get("retry-after")
    try:
        return float(value) if value is not None else None
    except ValueError:
        return None


class Client:
    """A wiredem server's API.

    Args:
        url: ``http://HOST[:PORT][/PREFIX]``; default ``$WIREDEM_SERVER``, else
            ``http://127.0.0.1:8080`` (as the ``wiredem`` command).
        token: the bearer token of a server started with ``--token-file``.
        token_file: a file holding it; default ``$WIREDEM_TOKEN_FILE``.
        timeout_s: limit for connecting and for each read (default 30 s).

    Job and study documents are returned as the server's JSON (dicts), with
    the keys docs/api.md lists. Errors the server answers are raised as
    :class:`~wiredem.errors.ApiError` with its body; an unreachable server as
    :class:`~wiredem.errors.NetworkError`.

    Thread safety: a Client holds no connection; one instance may be used
    from several threads.
    """

    def __init__(self, url: Optional[str] = None, token: Optional[str] = None,
                 token_file: Optional[Union[str, "os.PathLike[str]"]] = None, timeout_s: float = 30.0) -> None:
        url = url or os.environ.get("WIREDEM_SERVER") or "http://127.0.0.1:8080"
        parts = urllib.parse.urlsplit(url)
        if parts.scheme != "http" or not parts.hostname:
            raise WiredemError(f"server URL {url!r}: expected http://HOST[:PORT][/PREFIX] "
                               "(https is not served: use a tunnel or a local proxy)")
        self.url = url.rstrip("/")
        if token is None:
            token_file = token_file or os.environ.get("WIREDEM_TOKEN_FILE")
            if token_file:
                try:
                    token = Path(os.fspath(token_file)).read_text().strip()
                except OSError as e:
                    raise WiredemError(f"cannot read the token file {token_file}: {e.strerror}") from e
        self.token = token
        self.timeout_s = timeout_s
        #: Every request made, as (route name, query parameter names, header names): what the
        #: OpenAPI test holds against the served document.
        self.sent: List[Tuple[str, Tuple[str, ...], Tuple[str, ...]]] = []

    # ------------------------------------------------------------------ plumbing

    def _target(self, route: Route, path_params: Mapping[str, Any], query: Mapping[str, Any]) -> str:
        path = route.path
        for name, value in path_params.items():
            path = path.replace("{" + name + "}", urllib.parse.quote(str(value), safe=""))
        if "{" in path:
            raise WiredemError(f"{route.path}: a path parameter is missing")
        unknown = set(query) - set(route.query)
        if unknown:  # the table is what the OpenAPI test checks: nothing may bypass it
            raise WiredemError(f"{route.method} {route.path} takes no parameter {sorted(unknown)}")
        q = [(k, v) for k, v in query.items() if v is not None]
        return self.url + path + ("?" + urllib.parse.urlencode(q) if q else "")

    def _send(self, name: str, path_params: Optional[Mapping[str, Any]] = None,
              query: Optional[Mapping[str, Any]] = None, body: Optional[bytes] = None,
              headers: Optional[Mapping[str, str]] = None, what: str = "",
              sink: Optional[Callable[[int], Callable[[bytes], None]]] = None) -> _Reply:
        """One request of the route ``name``; raises ApiError for an error status.

        With ``sink``, a 2xx body is not kept: ``sink(status)`` gives the function
        its chunks are handed to.
        """
        route = ROUTES[name]
        query = {k: v for k, v in (query or {}).items() if v is not None}
        headers = dict(headers or {})
        unknown = set(headers) - set(route.headers)
        if unknown:
            raise WiredemError(f"{route.method} {route.path} sends no header {sorted(unknown)}")
        target = self._target(route, path_params or {}, query)
        self.sent.append((name, tuple(sorted(query)), tuple(sorted(headers))))
        if self.token:
            headers["Authorization"] = f"Bearer {self.token}"
        if body is not None:
            headers["Content-Type"] = "application/json"
        request = urllib.request.Request(target, data=body, headers=headers, method=route.method)
        try:
            with _OPENER.open(request, timeout=self.timeout_s) as response:
                status, reply_headers = response.status, dict(response.headers.items())
                if sink is None:
                    return _Reply(status, reply_headers, response.read())
                write = sink(status)
                while True:
                    chunk = response.read(1 << 16)
                    if not chunk:
                        break
                    write(chunk)
                return _Reply(status, reply_headers, b"")
        except urllib.error.HTTPError as e:
            raw = e.read() if e.fp is not None else b""
            raise self._api_error(e.code, dict(e.headers.items()) if e.headers else {}, raw,
                                  what or f"{route.method} {route.path}") from None
        except (urllib.error.URLError, OSError, ConnectionError) as e:
            reason = getattr(e, "reason", e)
            raise NetworkError(f"{what or route.path}: cannot reach {self.url}: {reason}") from e

    @staticmethod
    def _api_error(status: int, headers: Mapping[str, str], raw: bytes, what: str) -> ApiError:
        lower = {k.lower(): v for k, v in headers.items()}
        try:
            body: Any = json.loads(raw.decode("utf-8"))
        except (UnicodeDecodeError, ValueError):
            body = raw.decode("utf-8", "replace")
        err = body.get("error") if isinstance(body, dict) else None
        if isinstance(err, dict):
            return ApiError(status, err.get("code"), str(err.get("message", "")), err.get("field"),
                            err.get("details") or [], _retry_after(lower), body, what)
        return ApiError(status, None, str(body)[:200] or f"HTTP {status}", None, [], _retry_after(lower), body, what)

    def _json(self, name: str, what: str = "", **kw: Any) -> Any:
        return self._send(name, what=what, **kw).json()

    # ------------------------------------------------------------------ service

    def health(self) -> JSON:
        """``GET /v1/health``: status, version, queue and worker counts."""
        return self._json("getHealth")

    def openapi(self) -> JSON:
        """The server's OpenAPI 3 document (``GET /v1/openapi.json``)."""
        return self._json("getOpenApi")

    def job_spec_schema(self) -> JSON:
        """The job spec as a JSON Schema (``GET /v1/job-spec/schema``): every field, its range and default."""
        return self._json("getJobSpecSchema")

    # ------------------------------------------------------------------ jobs

    def submit(self, spec: SpecLike, idempotency_key: Optional[str] = None, retries: int = 3) -> JSON:
        """Submits a job spec (a dict, or the path of a JSON file); returns the job (state ``queued``).

        The server validates it with the job parser (docs/job-spec.md); an
        invalid spec raises ApiError ``invalid_job`` with every problem in
        ``details``. A fresh ``Idempotency-Key`` (or the one given) makes the
        retries of a lost reply (up to ``retries`` attempts) create one job only.
        """
        body = _load_document(spec)
        key = idempotency_key or secrets.token_hex(16)
        for attempt in range(1, retries + 1):
            try:
                return self._json("submitJob", body=body, headers={"Idempotency-Key": key}, what="submit")
            except NetworkError:
                if attempt == retries:
                    raise
                time.sleep(1.0)
        raise AssertionError("unreachable")

    def job(self, job_id: str) -> JSON:
        """``GET /v1/jobs/{id}``: state, stage, progress, eta_s, message, error, links, spec."""
        return self._json("getJob", path_params={"id": job_id}, what=f"job {job_id}")

    def jobs(self, state: Optional[str] = None, limit: Optional[int] = None, all_pages: bool = False) -> List[JSON]:
        """Jobs, newest first (one page of ``limit``, or every page with ``all_pages``)."""
        return self._pages("listJobs", "jobs", {"state": state, "limit": limit}, all_pages)

    def _pages(self, route: str, key: str, query: Dict[str, Any], all_pages: bool) -> List[JSON]:
        """The ``key`` list of one page of a listing route, or of every page (following ``next_cursor``)."""
        out: List[JSON] = []
        cursor: Optional[str] = None
        while True:
            page = self._json(route, query={**query, "cursor": cursor}, what=route)
            out.extend(page.get(key, []))
            cursor = page.get("next_cursor")
            if not all_pages or not cursor:
                return out

    def cancel(self, job_id: str) -> JSON:
        """Cancels a queued or running job; returns it (state ``cancelled``)."""
        return self._json("deleteJob", path_params={"id": job_id}, what=f"cancel {job_id}")

    def remove(self, job_id: str) -> None:
        """Deletes a job that has ended, with its files (``DELETE …?remove=true``)."""
        self._send("deleteJob", path_params={"id": job_id}, query={"remove": "true"}, what=f"remove {job_id}")

    def wait(self, job_id: str, interval_s: float = 1.0, timeout_s: Optional[float] = None,
             progress: Optional[Callable[[JSON], None]] = None, check: bool = True) -> JSON:
        """Polls a job until it ends and returns its last state.

        Args:
            interval_s: seconds between two polls.
            timeout_s: raise :class:`WaitTimeout` when the job has not ended after so long.
            progress: called with the job at every poll (its ``state``, ``stage``,
                ``progress`` 0–1, ``eta_s``, ``message``).
            check: raise :class:`JobFailed` / :class:`JobCancelled` when the job did
                not succeed (otherwise the job is returned whatever its end).

        Network errors (a restarting server) are retried for up to a minute.
        """
        job = self._poll(lambda: self.job(job_id), lambda j: j.get("state") in FINAL_STATES, interval_s,
                         timeout_s, progress, lambda j: f"job {job_id} still {j.get('state')} after {timeout_s:g} s")
        if check and job.get("state") == "failed":
            raise JobFailed(job)
        if check and job.get("state") == "cancelled":
            raise JobCancelled(job)
        return job

    @staticmethod
    def _poll(get: Callable[[], JSON], ended: Callable[[JSON], bool], interval_s: float, timeout_s: Optional[float],
              progress: Optional[Callable[[JSON], None]], late: Callable[[JSON], str]) -> JSON:
        """Calls ``get`` every ``interval_s`` until ``ended`` says so; network errors (a restarting
        server) are retried for up to a minute, as the ``wiredem`` command does."""
        started = time.monotonic()
        failing_since: Optional[float] = None
        while True:
            try:
                doc = get()
                failing_since = None
            except NetworkError:
                now = time.monotonic()
                failing_since = failing_since or now
                if now - failing_since > 60.0:
                    raise
                time.sleep(interval_s)
                continue
            if progress is not None:
                progress(doc)
            if ended(doc):
                return doc
            if timeout_s is not None and time.monotonic() - started > timeout_s:
                raise WaitTimeout(late(doc))
            time.sleep(interval_s)

    def summary(self, job_id: str) -> JSON:
        """The job's summary.json (409 ``not_succeeded`` until it has succeeded); docs/results.md."""
        return self._json("getJobSummary", path_params={"id": job_id}, what=f"summary of {job_id}")

    def download_result(self, job_id: str, path: Union[str, "os.PathLike[str]"],
                        progress: Optional[Callable[[int, int], None]] = None) -> Path:
        """Downloads the job's result.h5 to ``path``, resumably, as ``wiredem fetch`` does.

        The bytes go to ``PATH.part`` with the result's ETag in ``PATH.part.etag``;
        a later call resumes a part file of the same result from its size
        (``Range`` + ``If-Range``: the server sends the whole file if the result
        changed), starts over from a part of another result, and skips a complete
        file whose size and ETag (``PATH.etag``) match. ``progress(bytes, total)``
        is called as bytes arrive. Returns ``path``.
        """
        final = Path(os.fspath(path))
        final.parent.mkdir(parents=True, exist_ok=True)
        what = f"result of {job_id}"
        head = self._send("getJobResultHead", path_params={"id": job_id}, what=what)
        try:
            total = int(head.headers["content-length"])
        except (KeyError, ValueError):
            raise WiredemError(f"{what}: the server sent no Content-Length") from None
        etag = head.headers.get("etag")
        if not etag:
            raise WiredemError(f"{what}: the server sent no ETag")
        part = final.with_name(final.name + ".part")
        final_tag, part_tag = final.with_name(final.name + ".etag"), part.with_name(part.name + ".etag")

        def tag_of(p: Path) -> str:
            try:
                return p.read_text().splitlines()[0] if p.stat().st_size else ""
            except (OSError, IndexError):
                return ""

        if final.is_file() and final.stat().st_size == total and tag_of(final_tag) == etag:
            return final
        offset = part.stat().st_size if part.is_file() and tag_of(part_tag) == etag else 0
        if offset > total:
            offset = 0
        part_tag.write_text(etag + "\n")
        if offset < total or total == 0:
            reply = self._download(job_id, part, offset, etag, total, progress, what)
            if reply is None:  # 416: the part is not a prefix of this result
                reply = self._download(job_id, part, 0, etag, total, progress, what)
            if reply is None or reply.headers.get("etag") != etag:
                raise WiredemError(f"{what} changed while it was downloaded; download again")
        got = part.stat().st_size
        if got != total:
            raise NetworkError(f"{what}: got {got} of {total} bytes; download again to resume")
        os.replace(part, final)
        os.replace(part_tag, final_tag)
        return final

    def _download(self, job_id: str, part: Path, offset: int, etag: str, total: int,
                  progress: Optional[Callable[[int, int], None]], what: str) -> Optional[_Reply]:
        """One GET of result.h5 into ``part`` from ``offset``; None on 416 (the part is removed).

        A 206 continues the part; a 200 (If-Range did not match: the result
        changed) is the whole file, and the part is written afresh.
        """
        headers = {"Range": f"bytes={offset}-", "If-Range": etag} if offset > 0 else {}
        opened: List[Any] = []

        def open_part(status: int) -> Callable[[bytes], None]:
            resumed = offset if status == 206 else 0
            handle = open(part, "ab" if status == 206 else "wb")
            opened.append(handle)
            done = [resumed]

            def write(chunk: bytes) -> None:
                handle.write(chunk)
                done[0] += len(chunk)
                if progress is not None:
                    progress(done[0], total)
            return write

        try:
            return self._send("getJobResult", path_params={"id": job_id}, headers=headers, what=what,
                              sink=open_part)
        except ApiError as e:
            if e.status == 416:
                for h in opened:
                    h.close()
                part.unlink(missing_ok=True)
                return None
            raise
        finally:
            for h in opened:
                h.close()

    def fetch(self, job_id: str, directory: Union[str, "os.PathLike[str]"],
              progress: Optional[Callable[[int, int], None]] = None) -> Path:
        """Writes ``DIR/summary.json`` and ``DIR/result.h5`` (resumable) of a succeeded job; returns DIR.

        The folder is what ``wiredem fetch ID -o DIR`` writes; open it with :func:`wiredem.open`.
        """
        folder = Path(os.fspath(directory))
        folder.mkdir(parents=True, exist_ok=True)
        reply = self._send("getJobSummary", path_params={"id": job_id}, what=f"summary of {job_id}")
        tmp = folder / "summary.json.tmp"
        tmp.write_bytes(reply.body)
        os.replace(tmp, folder / "summary.json")
        self.download_result(job_id, folder / "result.h5", progress)
        return folder

    def result(self, job_id: str, directory: Union[str, "os.PathLike[str]"],
               progress: Optional[Callable[[int, int], None]] = None) -> "Result":
        """Fetches a succeeded job into ``directory`` and opens it (:class:`wiredem.Result`)."""
        from .results import open_result
        return open_result(self.fetch(job_id, directory, progress))

    # ------------------------------------------------------------------ result data (also while running)

    def tests(self, job_id: str) -> JSON:
        """``GET /v1/jobs/{id}/tests``: each test's name, rows, attributes, columns and snapshots.

        Answers while the job prepares or runs too (``"partial": true``, per test a ``state``).
        """
        return self._json("getJobTests", path_params={"id": job_id}, what=f"tests of {job_id}")

    def series(self, job_id: str, test: str, max_points: Optional[int] = None,
               columns: Optional[Iterable[str]] = None) -> "pandas.DataFrame":
        """A test's time series from the server as a DataFrame (units in ``frame.attrs["units"]``).

        ``test`` is its name (``sigma3_20000``); ``max_points`` keeps that many
        evenly spaced rows, the first and last among them; ``columns`` picks
        columns. While the test runs, the rows so far (``frame.attrs["partial"]``).
        The index is the stored row index.
        """
        import pandas as pd
        query: Dict[str, Any] = {"max_points": max_points,
                                 "columns": ",".join(columns) if columns is not None else None}
        doc = self._json("getJobTestsTestSeries", path_params={"id": job_id, "test": test}, query=query,
                         what=f"series {test} of {job_id}")
        frame = pd.DataFrame(doc["columns"], index=pd.Index(doc.get("row_index", []), name="row"))
        frame.attrs["units"] = dict(doc.get("units", {}))
        frame.attrs["test"] = doc.get("test", test)
        frame.attrs["partial"] = bool(doc.get("partial", False))
        return frame

    def wire_autocorrelation(self, job_id: str, test: str, snapshot: int) -> JSON:
        """The engine's autocorrelation of a snapshot's wire segment strains (``lag_m``,
        ``coefficients``, ``first_maximum_lag_m``, ``prominent_maximum_lag_m``, ``error``):
        the function summary.json's wire lags come from (docs/api.md)."""
        return self._json("getJobTestsTestSnapshotsKWireAutocorrelation",
                          path_params={"id": job_id, "test": test, "k": snapshot},
                          what=f"wire autocorrelation of {job_id} {test} snapshot {snapshot}")

    # ------------------------------------------------------------------ studies

    def submit_study(self, study: SpecLike) -> JSON:
        """Submits a parameter study (docs/studies.md; a dict or a path); returns the study with its jobs."""
        return self._json("submitStudy", body=_load_document(study), what="submit study")

    def study(self, study_id: str) -> JSON:
        """``GET /v1/studies/{id}``: the study, its document, per point the label, values and job."""
        return self._json("getStudy", path_params={"id": study_id}, what=f"study {study_id}")

    def studies(self, limit: Optional[int] = None, all_pages: bool = False) -> List[JSON]:
        """Studies, newest first, each with its jobs counted by state."""
        return self._pages("listStudies", "studies", {"limit": limit}, all_pages)

    def cancel_study(self, study_id: str) -> JSON:
        """Cancels every job of the study that has not ended."""
        return self._json("deleteStudy", path_params={"id": study_id}, what=f"cancel study {study_id}")

    def remove_study(self, study_id: str) -> None:
        """Deletes a study whose jobs have all ended, with its jobs and their files (``DELETE …?remove=true``)."""
        self._send("deleteStudy", path_params={"id": study_id}, query={"remove": "true"}, what=f"remove study {study_id}")

    def study_summary(self, study_id: str) -> JSON:
        """The study's summary (``points``, ``groups`` with φ and c over the seeds), as the server computed it."""
        return self._json("getStudySummary", path_params={"id": study_id}, what=f"summary of study {study_id}")

    def wait_study(self, study_id: str, interval_s: float = 1.0, timeout_s: Optional[float] = None,
                   progress: Optional[Callable[[JSON], None]] = None, check: bool = True) -> JSON:
        """Polls a study until every job has ended; raises :class:`StudyFailed` (with ``check``)
        when one did not succeed. Network errors are retried for up to a minute."""
        def counts(study: JSON) -> Dict[str, int]:
            return study.get("jobs_by_state") or {}

        study = self._poll(lambda: self.study(study_id),
                           lambda st: not any(n for s, n in counts(st).items() if s not in FINAL_STATES),
                           interval_s, timeout_s, progress,
                           lambda st: f"study {study_id} still has jobs to run after {timeout_s:g} s")
        if check and any(n for s, n in counts(study).items() if s != "succeeded"):
            raise StudyFailed(study)
        return study

    def fetch_study(self, study_id: str, directory: Union[str, "os.PathLike[str]"]) -> Path:
        """Writes the study's ``summary.json`` and each succeeded point's files in
        ``DIR/points/K/`` (what ``wiredem study fetch`` writes, but the CSV); returns DIR.
        Open it with :func:`wiredem.open_study`."""
        folder = Path(os.fspath(directory))
        folder.mkdir(parents=True, exist_ok=True)
        reply = self._send("getStudySummary", path_params={"id": study_id}, what=f"summary of study {study_id}")
        (folder / "summary.json").write_bytes(reply.body)
        for point in reply.json().get("points", []):
            if point.get("state") == "succeeded" and point.get("job_id"):
                self.fetch(point["job_id"], folder / "points" / str(point["index"]))
        return folder

    def study_results(self, study_id: str) -> "Study":
        """The study's summary and each succeeded point's summary.json, without result files
        (:class:`wiredem.Study`: :meth:`~wiredem.Study.tests` is the tidy frame)."""
        from .study import Study
        summary = self.study_summary(study_id)
        points: Dict[int, JSON] = {}
        seeds: Dict[int, Any] = {}
        for point in summary.get("points", []):
            index = int(point["index"])
            if point.get("job_id") and "seed" not in (point.get("values") or {}):
                seeds[index] = (self.job(point["job_id"]).get("spec") or {}).get("seed")  # the base's seed
            if point.get("state") == "succeeded" and point.get("job_id"):
                points[index] = self.summary(point["job_id"])
        return Study(summary, points, seeds=seeds)


