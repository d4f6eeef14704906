//! Prints the element count of the benchmark mesh (used to size `benches/continuum.rs`).
fn main() {
    let mut p = turf::continuum::IndentParams::hertz_example();
    p.mesh.elements_per_radius = 80.0;
    p.mesh.fine_depth = 1.0;
    p.mesh.fine_radius = 2.0;
    let r = turf::continuum::indent::resolve(&p).unwrap();
    let m = turf::continuum::mesh::graded_block(&r.block).unwrap();
    println!("{:?}", m.report());
}
