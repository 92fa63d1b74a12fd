//! Extended-pencil (QZ) solvers for the CARE and DARE.
