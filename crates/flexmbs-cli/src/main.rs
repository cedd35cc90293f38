//! The flexmbs command-line program.
fn main() {
    println!("flexmbs");
}
