"""``dcol.Error`` and ``dcol.Status``: the C ABI's statuses, as Python sees them."""

import enum

__all__ = ["Error", "Status"]


class Status(enum.IntEnum):
    """The C ABI's ``dcol_status`` values (``include/dcol.h``); fixed, never renumbered."""

    OK = 0
    NULL_POINTER = 1
    INVALID_SHAPE = 2
    INVALID_POSE = 3
    INVALID_OPTIONS = 4
    NOT_CONVERGED = 5
    INTERNAL = 6


class Error(Exception):
    """An error from dcol, with the C ABI's status and message.

    Attributes:
        status: the ``dcol_status`` number the C function returns (a ``dcol.Status``).
        message: the sentence ``dcol_last_error_message()`` gives: the C function, the
            argument, its value and the rule it broke, e.g.
            ``dcol_proximity: invalid pose: argument `pose2->position[1]` = NaN: must be finite``.
        result: for ``NOT_CONVERGED`` (5), what the C function writes all the same: the last
            iterate, in the form the Python function returns; ``None`` otherwise.
    """

    def __init__(self, message, status, result=None):
        super().__init__(message)
        self.message = message
        self.status = Status(status)
        self.result = result

    def __reduce__(self):
        return (type(self), (self.message, int(self.status), self.result))


Error.__module__ = "dcol"
Status.__module__ = "dcol"
