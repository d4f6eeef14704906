//! Axisymmetric finite-deformation FE indentation (seed chapter 4): mesh, elements, materials, contact, machine, driver.
