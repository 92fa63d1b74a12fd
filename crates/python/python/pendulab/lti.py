"""Linear time-invariant systems: python-control's and MATLAB's names over pendulab-lti."""

__all__: list = []
