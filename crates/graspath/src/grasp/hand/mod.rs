//! Hand models.
