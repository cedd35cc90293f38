//! Line numbers of key paths (`joint[2].a`, `body[0].mass`) in a model file, so that errors found
//! after deserialization (missing frames, bad values) name the line as schema errors do. The
//! locator is the one both model files share, [`flexmbs_io::toml_locate`].

pub use flexmbs_io::toml_locate::{line_of, line_of_path};
