//! From a scene to results: runs the stages the scene's plan asks for, in order, and reports.
