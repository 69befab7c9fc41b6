//! The DDS domain a node joins: ROS_DOMAIN_ID and ROS_AUTOMATIC_DISCOVERY_RANGE,
//! which ros2-client does not read by itself.

use std::net::{IpAddr, Ipv4Addr};

use rustdds::{DomainParticipant, DomainParticipantBuilder};

/// Errors in the DDS environment variables or while creating the participant.
#[derive(Debug, thiserror::Error)]
pub enum DomainError {
    /// ROS_DOMAIN_ID is not a number in 0..=232.
    #[error("ROS_DOMAIN_ID={0:?} is not a domain id (0..=232)")]
    DomainId(String),
    /// ROS_AUTOMATIC_DISCOVERY_RANGE has an unknown value.
    #[error(
        "ROS_AUTOMATIC_DISCOVERY_RANGE={0:?} is not one of SUBNET, LOCALHOST, OFF, SYSTEM_DEFAULT"
    )]
    Range(String),
    /// RustDDS could not create the participant.
    #[error("cannot create DDS participant in domain {domain}: {reason}")]
    Create {
        /// Domain id.
        domain: u16,
        /// RustDDS message.
        reason: String,
    },
}

/// How far discovery reaches (ROS 2 Iron+ `ROS_AUTOMATIC_DISCOVERY_RANGE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiscoveryRange {
    /// Every interface (ROS default).
    Subnet,
    /// Only peers on this host, over loopback.
    Localhost,
    /// No discovery of other processes.
    Off,
}

/// Where a node's participant lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DomainConfig {
    /// DDS domain id.
    pub domain_id: u16,
    /// Discovery reach.
    pub range: DiscoveryRange,
    /// Requested kernel receive buffer (SO_RCVBUF) for every socket.
    pub socket_receive_buffer: usize,
}

/// Receive buffer we ask for: large clouds arrive as bursts of datagrams.
pub const DEFAULT_RECEIVE_BUFFER: usize = 32 << 20;

impl DomainConfig {
    /// Reads ROS_DOMAIN_ID, ROS_AUTOMATIC_DISCOVERY_RANGE (and the older
    /// ROS_LOCALHOST_ONLY=1) through `get`, so tests need not touch the process env.
    pub fn from_lookup(get: impl Fn(&str) -> Option<String>) -> Result<Self, DomainError> {
        let domain_id = match get("ROS_DOMAIN_ID").filter(|s| !s.trim().is_empty()) {
            None => 0,
            Some(s) => s
                .trim()
                .parse::<u16>()
                .ok()
                .filter(|d| *d <= 232)
                .ok_or(DomainError::DomainId(s))?,
        };
        let range = match get("ROS_AUTOMATIC_DISCOVERY_RANGE")
            .map(|s| s.trim().to_ascii_uppercase())
            .filter(|s| !s.is_empty())
        {
            None if get("ROS_LOCALHOST_ONLY").as_deref() == Some("1") => DiscoveryRange::Localhost,
            None => DiscoveryRange::Subnet,
            Some(s) => match s.as_str() {
                "SUBNET" | "SYSTEM_DEFAULT" => DiscoveryRange::Subnet,
                "LOCALHOST" => DiscoveryRange::Localhost,
                "OFF" => DiscoveryRange::Off,
                _ => return Err(DomainError::Range(s)),
            },
        };
        Ok(Self {
            domain_id,
            range,
            socket_receive_buffer: DEFAULT_RECEIVE_BUFFER,
        })
    }

    /// Reads the configuration from the process environment.
    pub fn from_env() -> Result<Self, DomainError> {
        Self::from_lookup(|k| std::env::var(k).ok())
    }

    /// Creates the RustDDS participant for this configuration.
    pub fn participant(&self) -> Result<DomainParticipant, DomainError> {
        let mut b = DomainParticipantBuilder::new(self.domain_id)
            .socket_receive_buffer_size(self.socket_receive_buffer);
        b = match self.range {
            DiscoveryRange::Subnet => b,
            DiscoveryRange::Localhost => b
                .with_only_networks([IpAddr::V4(Ipv4Addr::LOCALHOST)])
                .same_host_loopback(true),
            DiscoveryRange::Off => b
                .with_only_networks(Vec::<IpAddr>::new())
                .same_host_loopback(false),
        };
        b.build().map_err(|e| DomainError::Create {
            domain: self.domain_id,
            reason: e.to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(pairs: &[(&str, &str)]) -> Result<DomainConfig, DomainError> {
        let pairs: Vec<(String, String)> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        DomainConfig::from_lookup(move |k| {
            pairs.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone())
        })
    }

    #[test]
    fn reads_domain_and_range() {
        let c = cfg(&[
            ("ROS_DOMAIN_ID", "42"),
            ("ROS_AUTOMATIC_DISCOVERY_RANGE", "localhost"),
        ])
        .unwrap();
        assert_eq!((c.domain_id, c.range), (42, DiscoveryRange::Localhost));
        let c = cfg(&[]).unwrap();
        assert_eq!((c.domain_id, c.range), (0, DiscoveryRange::Subnet));
        let c = cfg(&[("ROS_LOCALHOST_ONLY", "1")]).unwrap();
        assert_eq!(c.range, DiscoveryRange::Localhost);
    }

    #[test]
    fn rejects_bad_values() {
        assert!(matches!(
            cfg(&[("ROS_DOMAIN_ID", "300")]),
            Err(DomainError::DomainId(_))
        ));
        assert!(matches!(
            cfg(&[("ROS_DOMAIN_ID", "x")]),
            Err(DomainError::DomainId(_))
        ));
        assert!(matches!(
            cfg(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "MOON")]),
            Err(DomainError::Range(_))
        ));
    }
}
