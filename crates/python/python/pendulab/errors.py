"""The exceptions pendulab raises (created by ``pendulab._native``).

::

    Exception
    └── Error                       every error raised by pendulab
        ├── ShapeError              (also ValueError) wrong dimensions or shape
        ├── NotFiniteError          (also ValueError) NaN or ±Inf in an argument
        ├── InvalidArgumentError    (also ValueError) a value that is not allowed
        ├── LinAlgError             (also numpy.linalg.LinAlgError, a ValueError)
        │   ├── NotStabilizableError   no stabilising Riccati solution
        │   └── NotControllableError   poles cannot be assigned
        └── InfeasibleError         an LMI/SOS synthesis found no solution (``status``,
                                    ``certificate_valid``)

The message is the Rust library's, word for word; errors from pendulab-lti carry the Rust
variant's name in ``err.variant`` (e.g. ``"NotStabilizable"``).
"""

from ._native import (
    Error,
    InfeasibleError,
    InvalidArgumentError,
    LinAlgError,
    NotControllableError,
    NotFiniteError,
    NotStabilizableError,
    ShapeError,
)

__all__ = [
    "Error",
    "ShapeError",
    "NotFiniteError",
    "InvalidArgumentError",
    "LinAlgError",
    "NotStabilizableError",
    "NotControllableError",
    "InfeasibleError",
]
