//! `flexmbs reduce` stores the modal stress fields (group `stress`) of a body reduced from an FE
//! model, bitwise those a multibody model computes from the same FE model file.

use flexmbs_io::body_file::read_body_file;
use flexmbs_io::model_check::FeModelSource;
use flexmbs_reduce::pipeline::{prepare, run_reduction};
use flexmbs_reduce::stress::modal_stress_fields;
use std::path::Path;
use std::process::Command;

#[test]
fn reduce_stores_modal_stress_fields() {
    let dir = flexmbs_io::test_tools::scratch_dir("reduce_stress");
    for name in ["cantilever_beam", "solid_link"] {
        let part = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(format!("../../examples/mbs/parts/{name}.toml"));
        let out = dir.join(format!("{name}.fmb.h5"));
        let o = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
            .args(["-q", "reduce"])
            .arg(&part)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let msg = String::from_utf8_lossy(&o.stdout);
        assert!(msg.contains("modal stress fields"), "{msg}");
        let f = read_body_file(&out).unwrap();
        let src = FeModelSource::read(&part).unwrap();
        let spec = &src.model.body;
        let prepared = prepare(spec, part.parent().unwrap(), &mut |_| {}).unwrap();
        let body = run_reduction(spec, &prepared, &mut |_| {}).unwrap();
        let expected = modal_stress_fields(spec, &prepared, &body).unwrap();
        assert_eq!(f.stress.as_ref(), Some(&expected), "{name}");
        assert!(expected.fields.norm_max() > 0.0);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
