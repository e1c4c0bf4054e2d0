//! Small robot files that several targets write or mutate, and the writing of an input file.

use std::path::{Path, PathBuf};

/// Writes `bytes` to `name` in `dir` and returns its path. A failed write shows up as a read
/// error in the target, which is not a finding.
pub fn write_input(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    let _ = std::fs::write(&path, bytes);
    path
}

/// A three-link arm (base → l1 → tip, two revolute joints) named by generated task files.
pub const SMALL_ROBOT_URDF: &str = r#"<?xml version="1.0"?>
<robot name="small">
  <link name="base"/>
  <link name="l1"/>
  <link name="tip"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.5" upper="2.5" effort="10" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="tip"/>
    <origin xyz="0.4 0 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
</robot>
"#;
