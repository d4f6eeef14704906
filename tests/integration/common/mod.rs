//! Scene texts shared by integration tests (not a test target of its own).

/// The 4-tube, 1 µm turf of tests/integration/discrete_compression.rs (4 tubes of 8 segments in a 200 nm
/// periodic box), compressed to 30 % in 5 Newton steps and back, fitted by homogenize.
pub const SMALL_TURF_SCENE: &str = r#"
[scene]
name = "discrete-pipeline-test"
seed = 5
[turf]
density = "1e10 1/cm^2"
box = ["200 nm", "200 nm"]
[turf.tube]
r_o = "20 nm"
r_i = "17.3 nm"
youngs = "0.4 TPa"
segment = "125 nm"
[turf.growth]
length = "1 um"
length_spread = 0.05
tilt = 0.005
waviness = "3 nm"
wavelength = "700 nm"
[turf.vdw]
gamma_line = "1 nN"
[compression]
to = 0.3
steps = 5
unload = true
solver = "newton"
tolerance = "1e-6 nN"
[homogenize]
curve = "loading"
[output]
vtk = true
plots = false
"#;
