//! Loads each file named on the command line and prints the outcome and the time it took
//! (measure memory with `/usr/bin/time -v`).
fn main() {
    for path in std::env::args().skip(1) {
        let start = std::time::Instant::now();
        let outcome = match hya_urdf::load_file(&path) {
            Ok(loaded) => format!("loaded, {} joints", loaded.model.dof()),
            Err(e) => format!("refused: {}", e.problem),
        };
        println!("{path}: {outcome} ({:.3} s)", start.elapsed().as_secs_f64());
    }
}
