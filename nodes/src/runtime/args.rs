//! The `--ros-args` part of a node's command line, as ROS 2 nodes accept it.

use std::path::PathBuf;

/// Errors in the `--ros-args` section of a command line.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum ArgsError {
    /// A flag that needs a value came last.
    #[error("`{flag}` needs a value after it")]
    MissingValue {
        /// The flag, e.g. `--params-file`.
        flag: String,
    },
    /// A `-p` or `-r` argument without `:=`.
    #[error("`{arg}` is not of the form name:=value")]
    NotAssignment {
        /// The offending argument.
        arg: String,
    },
    /// Something inside `--ros-args` this runtime does not understand.
    #[error(
        "unsupported ROS argument `{arg}` (supported: --params-file F, -p name:=value, -r __node:=N, -r __ns:=NS, --log-level L)"
    )]
    Unsupported {
        /// The offending argument.
        arg: String,
    },
}

/// What a node was told on its command line inside `--ros-args ... [--]`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RosArgs {
    /// Params files in the order given; later ones override earlier ones.
    pub params_files: Vec<PathBuf>,
    /// `-p name:=value` overrides in order (value is YAML text).
    pub overrides: Vec<(String, String)>,
    /// `-r __node:=NAME`.
    pub node_name: Option<String>,
    /// `-r __ns:=/NS`.
    pub namespace: Option<String>,
    /// `--log-level LEVEL`.
    pub log_level: Option<String>,
}

impl RosArgs {
    /// Splits `argv` (without the program name) into the node's own arguments
    /// and the parsed `--ros-args` sections (there may be several, each ended by
    /// `--` or the end of the line).
    pub fn split(argv: &[String]) -> Result<(Vec<String>, RosArgs), ArgsError> {
        let mut own = Vec::new();
        let mut ros = RosArgs::default();
        let mut it = argv.iter();
        while let Some(a) = it.next() {
            if a != "--ros-args" {
                own.push(a.clone());
                continue;
            }
            while let Some(a) = it.next() {
                let mut value = |flag: &str| {
                    it.next().cloned().ok_or_else(|| ArgsError::MissingValue {
                        flag: flag.to_string(),
                    })
                };
                match a.as_str() {
                    "--" => break,
                    "--params-file" => ros.params_files.push(PathBuf::from(value(a)?)),
                    "-p" | "--param" => {
                        let v = value(a)?;
                        ros.overrides.push(assignment(&v)?);
                    }
                    "-r" | "--remap" => {
                        let v = value(a)?;
                        match assignment(&v)? {
                            (k, n) if k == "__node" || k == "__name" => ros.node_name = Some(n),
                            (k, n) if k == "__ns" => ros.namespace = Some(n),
                            _ => return Err(ArgsError::Unsupported { arg: v }),
                        }
                    }
                    "--log-level" => ros.log_level = Some(value(a)?),
                    other => {
                        return Err(ArgsError::Unsupported {
                            arg: other.to_string(),
                        });
                    }
                }
            }
        }
        Ok((own, ros))
    }
}

fn assignment(arg: &str) -> Result<(String, String), ArgsError> {
    match arg.split_once(":=") {
        Some((k, v)) if !k.is_empty() => Ok((k.to_string(), v.to_string())),
        _ => Err(ArgsError::NotAssignment {
            arg: arg.to_string(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(v: &[&str]) -> Vec<String> {
        v.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn splits_own_args_from_ros_args() {
        let (own, ros) = RosArgs::split(&s(&[
            "--verbose",
            "--ros-args",
            "--params-file",
            "a.yaml",
            "-p",
            "rate:=2.5",
            "-r",
            "__node:=pub2",
            "--",
            "tail",
        ]))
        .unwrap();
        assert_eq!(own, s(&["--verbose", "tail"]));
        assert_eq!(ros.params_files, vec![PathBuf::from("a.yaml")]);
        assert_eq!(ros.overrides, vec![("rate".into(), "2.5".into())]);
        assert_eq!(ros.node_name.as_deref(), Some("pub2"));
    }

    #[test]
    fn bad_ros_args_are_errors() {
        assert_eq!(
            RosArgs::split(&s(&["--ros-args", "-p", "rate=2"])),
            Err(ArgsError::NotAssignment {
                arg: "rate=2".into()
            })
        );
        assert_eq!(
            RosArgs::split(&s(&["--ros-args", "--params-file"])),
            Err(ArgsError::MissingValue {
                flag: "--params-file".into()
            })
        );
        assert!(matches!(
            RosArgs::split(&s(&["--ros-args", "--enclave", "x"])),
            Err(ArgsError::Unsupported { .. })
        ));
    }
}
