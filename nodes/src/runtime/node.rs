//! One running ROS 2 node: domain, parameters, logging, clock, publishers and
//! subscriptions, and an orderly stop.

use std::process::ExitCode;
use std::time::Duration;

use std::sync::{Arc, Mutex};

use futures::StreamExt;
use ros2_client::{
    Context, MessageTypeName, Name, Node, NodeName, NodeOptions, Publisher, QosProfile,
    Subscription,
};
use serde::de::DeserializeOwned;
use skyground_msgs::RosMessage;
use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::rosgraph_msgs::Clock;
use skyground_msgs::std_msgs::Header;

use super::args::{ArgsError, RosArgs};
use super::creation_watch::{Armed, CreationWatch};
use super::domain::{DomainConfig, DomainError};
use super::log::{Level, Logger};
use super::param_services;
use super::params::{ParamSet, ParamsError};
use super::qos;
use super::shutdown::Shutdown;
use super::specs::NodeSpec;

/// Why a node could not start or run.
#[derive(Debug, thiserror::Error)]
pub enum RuntimeError {
    /// Bad `--ros-args`.
    #[error(transparent)]
    Args(#[from] ArgsError),
    /// Bad params.
    #[error(transparent)]
    Params(#[from] ParamsError),
    /// A params value outside its range (the library's check names it).
    #[error(transparent)]
    OutOfRange(#[from] skyground_core::params::ParamError),
    /// Bad DDS environment.
    #[error(transparent)]
    Domain(#[from] DomainError),
    /// A name that ROS 2 does not accept.
    #[error("invalid ROS name `{name}`: {reason}")]
    Name {
        /// The name.
        name: String,
        /// Why.
        reason: String,
    },
    /// ros2-client failed to create an entity.
    #[error("cannot create {what}: {reason}")]
    Create {
        /// What was being created.
        what: String,
        /// ros2-client's message.
        reason: String,
    },
    /// The node's own work failed.
    #[error("{0}")]
    Node(String),
}

/// A started node. Drop order matters to RustDDS: use [`NodeRuntime::stop`].
pub struct NodeRuntime {
    /// Node name (after `-r __node:=`).
    pub name: String,
    /// Merged parameters, as at start-up.
    pub params: ParamSet,
    /// The parameters now: start-up values with the live ones set since.
    current: Arc<Mutex<ParamSet>>,
    /// Logger to stderr and /rosout.
    pub log: Logger,
    /// Stop signal (SIGINT/SIGTERM or [`Shutdown::trigger`]).
    pub shutdown: Shutdown,
    /// The DDS domain joined.
    pub domain: DomainConfig,
    node: Node,
    context: Context,
    sim_time: Option<Arc<Mutex<Time>>>,
    creation: CreationWatch,
}

impl NodeRuntime {
    /// Reads the environment and the `--ros-args`, joins the domain and starts
    /// the node's spinner. Must run inside a tokio runtime.
    pub fn start(spec: &NodeSpec, ros: &RosArgs) -> Result<Self, RuntimeError> {
        let name = ros
            .node_name
            .clone()
            .unwrap_or_else(|| spec.name.to_string());
        let namespace = ros.namespace.clone().unwrap_or_else(|| "/".to_string());
        let mut params = ParamSet::default();
        params.merge_yaml(
            spec.default_params,
            spec.name,
            &format!("config/{}.yaml", spec.name),
        )?;
        for f in &ros.params_files {
            params.merge_file(f, &name)?;
        }
        for (k, v) in &ros.overrides {
            params.set_override(k, v)?;
        }
        let level = ros
            .log_level
            .as_deref()
            .map(|s| {
                Level::parse(s)
                    .ok_or_else(|| RuntimeError::Node(format!("unknown --log-level {s}")))
            })
            .transpose()?
            .unwrap_or(Level::Info);
        super::log::install_library_log(&name);
        let creation = CreationWatch::exiting(&name);
        let domain = DomainConfig::from_env()?;
        let armed = creation.guard("the DDS participant");
        let context = Context::from_domain_participant(domain.participant()?).map_err(|e| {
            RuntimeError::Create {
                what: "ROS 2 context".into(),
                reason: e.to_string(),
            }
        })?;
        drop(armed);
        let node_name = NodeName::new(&namespace, &name).map_err(|e| RuntimeError::Name {
            name: format!("{namespace}/{name}"),
            reason: format!("{e:?}"),
        })?;
        let current = Arc::new(Mutex::new(params.clone()));
        let options = param_services::declare(
            NodeOptions::new().enable_rosout(true),
            spec,
            &name,
            &params,
            current.clone(),
        );
        let armed = creation.guard(&format!("node {name}"));
        let mut node = context
            .new_node(node_name, options)
            .map_err(|e| RuntimeError::Create {
                what: format!("node {name}"),
                reason: format!("{e:?}"),
            })?;
        let spinner = node.spinner().map_err(|e| RuntimeError::Create {
            what: "spinner".into(),
            reason: e.to_string(),
        })?;
        drop(armed);
        tokio::spawn(spinner.spin());
        let log = Logger::new(&name, Some(node.logging_handle()), level);
        let mut rt = Self {
            name,
            params,
            current,
            log,
            shutdown: Shutdown::install(),
            domain,
            node,
            context,
            sim_time: None,
            creation,
        };
        // Always listening, so a `use_sim_time` set at run time (as `ros2
        // param set` does) switches the clock at once; /clock's rate is low.
        rt.follow_clock()?;
        Ok(rt)
    }

    /// Subscribes to /clock (rosgraph_msgs/Clock, best effort as rclpy's
    /// TimeSource does). ros2-client's own sim time listens for a
    /// `builtin_interfaces/Time` type on /clock, which no ROS 2 clock
    /// publisher matches, so the runtime keeps the time itself.
    fn follow_clock(&mut self) -> Result<(), RuntimeError> {
        let sub = self.subscription::<Clock>("/clock", qos::sensor(1))?;
        let latest = Arc::new(Mutex::new(Time::default()));
        let slot = latest.clone();
        tokio::spawn(async move {
            let stream = sub.async_stream();
            futures::pin_mut!(stream);
            while let Some(m) = stream.next().await {
                if let (Ok((c, _)), Ok(mut t)) = (m, slot.lock()) {
                    *t = c.clock;
                }
            }
        });
        self.sim_time = Some(latest);
        Ok(())
    }

    /// The node's parameters as its typed struct.
    pub fn params<T: DeserializeOwned>(&self) -> Result<T, RuntimeError> {
        Ok(self.params.parse(&self.name)?)
    }

    /// The node's parameters as they are now: [`NodeSpec::live`] ones may
    /// have been set since start-up (read this where a set should take effect).
    pub fn current_params<T: DeserializeOwned>(&self) -> Result<T, RuntimeError> {
        let set = self
            .current
            .lock()
            .map_err(|_| RuntimeError::Node("parameter set poisoned".into()))?;
        Ok(set.parse(&self.name)?)
    }

    /// Current time: /clock's while `use_sim_time` is set (read live, so a
    /// set through the parameter services takes effect at the next call),
    /// else the system clock.
    pub fn now(&self) -> Time {
        // ros2-client keeps `use_sim_time` itself (its set never reaches
        // our parameter action), so its store is the one to ask.
        let simulated = matches!(
            self.node.get_parameter("use_sim_time"),
            Some(ros2_client::ParameterValue::Boolean(true))
        );
        if simulated && let Some(t) = &self.sim_time {
            return t.lock().map(|t| *t).unwrap_or_default();
        }
        let ns = self.node.time_now_not_simulated().to_nanos();
        Time {
            sec: i32::try_from(ns.div_euclid(1_000_000_000)).unwrap_or(i32::MAX),
            nanosec: u32::try_from(ns.rem_euclid(1_000_000_000)).unwrap_or(0),
        }
    }

    /// A header stamped [`Self::now`] in frame `frame_id`.
    pub fn header(&self, frame_id: &str) -> Header {
        Header {
            stamp: self.now(),
            frame_id: frame_id.into(),
        }
    }

    /// The ros2-client node, for what this runtime does not wrap.
    pub fn node(&mut self) -> &mut Node {
        &mut self.node
    }

    /// The ros2-client context.
    pub fn context(&self) -> &Context {
        &self.context
    }

    /// Marks the creation of a DDS entity this runtime does not wrap (see
    /// [`CreationWatch`]) until the guard drops.
    pub fn creating(&self, what: &str) -> Armed<'_> {
        self.creation.guard(what)
    }

    /// Runs `f` if a stuck DDS creation ends the node (see
    /// [`CreationWatch::before_exit`]): where a node closes what it writes.
    pub fn before_stuck_exit(&self, f: impl FnOnce() + Send + 'static) {
        self.creation.before_exit(f);
    }

    /// Creates (or finds) the DDS topic for message type `M`.
    pub fn topic<M: RosMessage>(
        &self,
        topic: &str,
        qos: &QosProfile,
    ) -> Result<rustdds::Topic, RuntimeError> {
        let name = Name::parse(topic).map_err(|e| RuntimeError::Name {
            name: topic.to_string(),
            reason: format!("{e:?}"),
        })?;
        let (pkg, ty) = split_type_name(M::TYPE_NAME);
        let _armed = self.creation.guard(&format!("topic {topic}"));
        self.node
            .create_topic(&name, MessageTypeName::new(pkg, ty), qos)
            .map_err(create_error(format!("topic {topic}")))
    }

    /// A publisher of `M` on `topic`.
    pub fn publisher<M: RosMessage>(
        &mut self,
        topic: &str,
        qos: QosProfile,
    ) -> Result<Publisher<M>, RuntimeError> {
        let t = self.topic::<M>(topic, &qos)?;
        let _armed = self.creation.guard(&format!("publisher on {topic}"));
        self.node
            .create_publisher(&t, Some(qos))
            .map_err(create_error(format!("publisher on {topic}")))
    }

    /// A subscription to `M` on `topic`.
    pub fn subscription<M: RosMessage>(
        &mut self,
        topic: &str,
        qos: QosProfile,
    ) -> Result<Subscription<M>, RuntimeError> {
        let t = self.topic::<M>(topic, &qos)?;
        let _armed = self.creation.guard(&format!("subscription to {topic}"));
        self.node
            .create_subscription(&t, Some(qos))
            .map_err(create_error(format!("subscription to {topic}")))
    }

    /// Stops the spinner and drops node and context in the order RustDDS needs
    /// to tell its peers goodbye.
    pub async fn stop(self) {
        self.node.stop_spinner();
        tokio::time::sleep(Duration::from_millis(50)).await;
        drop(self.node);
        drop(self.context);
    }
}

/// Splits `pkg/msg/Type` (or `pkg/Type`) into package and type.
pub fn split_type_name(full: &str) -> (&str, &str) {
    let pkg = full.split('/').next().unwrap_or(full);
    let ty = full.rsplit('/').next().unwrap_or(full);
    (pkg, ty)
}

/// Runs a node binary: parses the command line, starts the node inside a
/// tokio runtime, runs `body`, stops in order. Errors print and exit 1.
pub fn run_node<F>(spec: NodeSpec, body: F) -> ExitCode
where
    F: AsyncFnOnce(&mut NodeRuntime, Vec<String>) -> Result<(), RuntimeError>,
{
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let (own, ros) = match RosArgs::split(&argv) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("{}: {e}", spec.name);
            return ExitCode::from(2);
        }
    };
    run_with(spec, ros, own, body)
}

/// Like [`run_node`] with the command line already split (for CLI tools that
/// run a node of their own).
pub fn run_with<F>(spec: NodeSpec, ros: RosArgs, own: Vec<String>, body: F) -> ExitCode
where
    F: AsyncFnOnce(&mut NodeRuntime, Vec<String>) -> Result<(), RuntimeError>,
{
    let rt = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("{}: cannot start tokio: {e}", spec.name);
            return ExitCode::FAILURE;
        }
    };
    rt.block_on(async move {
        let mut node = match NodeRuntime::start(&spec, &ros) {
            Ok(n) => n,
            Err(e) => {
                eprintln!("{}: {e}", spec.name);
                return ExitCode::FAILURE;
            }
        };
        let code = match body(&mut node, own).await {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                node.log.error(&e.to_string());
                ExitCode::FAILURE
            }
        };
        node.stop().await;
        code
    })
}

/// Maps a DDS creation error to [`RuntimeError::Create`] naming `what`.
fn create_error<E: std::fmt::Display>(what: String) -> impl FnOnce(E) -> RuntimeError {
    move |e| RuntimeError::Create {
        what,
        reason: e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_names_split() {
        assert_eq!(
            split_type_name("sensor_msgs/msg/PointCloud2"),
            ("sensor_msgs", "PointCloud2")
        );
        assert_eq!(split_type_name("nav_msgs/Path"), ("nav_msgs", "Path"));
    }
}
