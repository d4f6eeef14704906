//! Closed-form contact mechanics and turf micromechanics (seed chapters 2 and 3).
