//! The one-shot grasp model.
