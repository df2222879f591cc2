"""Exceptions of the wiredem package.

Every error the package raises is a :class:`WiredemError`. A refusal by the
server is an :class:`ApiError` carrying the server's error body (docs/api.md,
"Conventions"): its stable ``code``, the one-line ``message``, the ``field``
it names and, for a job spec with several problems, every one in ``details``.
"""
from __future__ import annotations

from typing import Any, Dict, List, Optional


class WiredemError(Exception):
    """Base class of every error raised by the wiredem package."""


class ApiError(WiredemError):
    """The server answered with an error status (4xx, 5xx).

    Attributes:
        status: the HTTP status (400, 404, 409, 429, …).
        code: the server's stable error code (``invalid_job``, ``not_found``, …),
            or ``None`` when the body was not the documented error object.
        message: the server's one-line message (or the HTTP reason).
        field: the field, parameter or header the error names, or ``None``.
        details: every problem of an invalid job spec or study, each a dict
            ``{"field": …, "message": …}``; empty otherwise.
        retry_after_s: the ``Retry-After`` header in seconds (429, 503), or ``None``.
        body: the error body as the server sent it (parsed JSON, or text).
    """

    def __init__(self, status: int, code: Optional[str], message: str, field: Optional[str] = None,
                 details: Optional[List[Dict[str, Any]]] = None, retry_after_s: Optional[float] = None,
                 body: Any = None, what: str = "") -> None:
        self.status = status
        self.code = code
        self.message = message
        self.field = field
        self.details = list(details or [])
        self.retry_after_s = retry_after_s
        self.body = body
        text = f"{what}: " if what else ""
        text += f"{message} (HTTP {status}" + (f", {code}" if code else "") + ")"
        for d in self.details:
            if d.get("message") and d.get("message") != message:
                text += f"\n  {d.get('field') or ''}: {d['message']}" if d.get("field") else f"\n  {d['message']}"
        super().__init__(text)


class NetworkError(WiredemError):
    """The server could not be reached, or the connection broke (no HTTP reply)."""


class JobFailed(WiredemError):
    """A job waited for ended ``failed``; ``job`` is its last state, ``job["error"]`` why."""

    def __init__(self, job: Dict[str, Any]) -> None:
        self.job = job
        super().__init__(f"job {job.get('id')} failed: {job.get('error')}")


class JobCancelled(WiredemError):
    """A job waited for was cancelled; ``job`` is its last state."""

    def __init__(self, job: Dict[str, Any]) -> None:
        self.job = job
        super().__init__(f"job {job.get('id')} was cancelled" + (f": {job['error']}" if job.get("error") else ""))


class StudyFailed(WiredemError):
    """A study waited for ended with jobs that did not succeed; ``study`` is its last state."""

    def __init__(self, study: Dict[str, Any]) -> None:
        self.study = study
        counts = study.get("jobs_by_state") or {}
        super().__init__(f"study {study.get('id')} ended with jobs that did not succeed: "
                         + ", ".join(f"{n} {s}" for s, n in counts.items() if n))


class WaitTimeout(WiredemError):
    """``timeout_s`` passed before the job or study ended."""


class ResultError(WiredemError):
    """A result file or folder lacks what was asked of it, or is not a wiredem result."""
