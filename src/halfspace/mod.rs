//! Axisymmetric small-strain half-space with Lennard-Jones surface tractions (Greenwood / Attard–Parker class).
