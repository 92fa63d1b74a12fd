import numpy as np

class Error(Exception):
    """Base class of every error pendulab raises."""

    variant: str
    """The Rust error variant's name (errors from pendulab-lti), e.g. ``"NotStabilizable"``."""

class ShapeError(Error, ValueError): ...
class NotFiniteError(Error, ValueError): ...
class InvalidArgumentError(Error, ValueError): ...
class LinAlgError(Error, np.linalg.LinAlgError): ...
class NotStabilizableError(LinAlgError): ...
class NotControllableError(LinAlgError): ...

__all__: list[str]

class InfeasibleError(Error):
    status: str
    """The solver's outcome, e.g. ``"infeasible"``."""
    certificate_valid: bool
    """Whether a Farkas certificate of infeasibility checks out."""
