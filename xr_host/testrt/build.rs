//! Marks the test runtime `-z nodelete`: the loader dlcloses a runtime when
//! its last instance goes, and the script's fired faults and step counter
//! must survive an instance-loss retry.
fn main() {
    println!("cargo:rustc-cdylib-link-arg=-Wl,-z,nodelete");
}
