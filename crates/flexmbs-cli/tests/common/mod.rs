//! Models shared by the command-line tests.

/// A rigid pendulum (1 kg, 1 m, revolute joint) that runs for `t_end` with generalized-alpha at
/// 1 ms steps, writing every `every`-th step and no animation: a run long enough to be
/// interrupted or killed while it writes.
pub fn long_pendulum(t_end: &str, every: u32) -> String {
    format!(
        r#"
[model]
name = "long_pendulum"
gravity = [0, -9.81, 0]

[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "{t_end}"

[[body]]
name = "arm"
type = "rigid"
mass = 1
inertia = [1e-4, 0.0834, 0.0834]
position = [0.5, 0, 0]

[[frame]]
name = "hinge"
body = "ground"

[[frame]]
name = "top"
body = "arm"
position = [-0.5, 0, 0]

[[joint]]
name = "pin"
type = "revolute"
a = "hinge"
b = "top"

[output]
every = {every}
animation = false
"#
    )
}
