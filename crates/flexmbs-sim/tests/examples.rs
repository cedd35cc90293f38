//! Every example model in `examples/mbs/` compiles (parses, reduces its FE bodies, builds the
//! engine model and the initial state). Examples with a CalculiX body are skipped, with the reason
//! printed, when `ccx` is not installed (CI installs it).

use std::path::Path;

#[test]
fn all_examples_compile() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = std::fs::read_to_string(&path).unwrap();
            if path
                .file_name()
                .is_some_and(|f| f.to_string_lossy().starts_with("calculix"))
                && flexmbs_io::test_tools::ccx_or_skip(&format!(
                    "all_examples_compile ({})",
                    path.display()
                ))
                .is_none()
            {
                n += 1;
                continue;
            }
            assert!(flexmbs_sim::is_multibody_model(&text), "{}", path.display());
            let cm = flexmbs_sim::load_model(&path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert!(
                cm.model.nq > 0 && !cm.bodies.is_empty(),
                "{}",
                path.display()
            );
            n += 1;
        }
    }
    assert!(n >= 19, "expected at least 19 example models, found {n}");
    // FE body files are not multibody models
    let fe = std::fs::read_to_string(dir.join("parts/rod.toml")).unwrap();
    assert!(!flexmbs_sim::is_multibody_model(&fe));
}
