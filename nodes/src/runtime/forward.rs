//! A subscription drained into a channel by a task of its own, so a node's
//! main loop reads its inputs with `try_recv` between simulation steps.

use futures::StreamExt;
use ros2_client::QosProfile;
use skyground_msgs::RosMessage;
use tokio::sync::mpsc;

use super::node::{NodeRuntime, RuntimeError};

/// Subscribes to `topic` and sends every message, as `convert` makes it,
/// into `tx`. Unreadable messages are logged; so is a send that fails
/// (the receiver is gone: the node is stopping, or its loop died), after
/// which the task ends.
pub fn forward<M, T>(
    rt: &mut NodeRuntime,
    topic: &str,
    qos: QosProfile,
    tx: mpsc::Sender<T>,
    convert: fn(&M) -> T,
) -> Result<(), RuntimeError>
where
    M: RosMessage,
    T: Send + 'static,
{
    let sub = rt.subscription::<M>(topic, qos)?;
    let (log, topic) = (rt.log.clone(), topic.to_owned());
    tokio::spawn(async move {
        let s = sub.async_stream();
        futures::pin_mut!(s);
        while let Some(m) = s.next().await {
            match m {
                Ok((m, _)) => {
                    if tx.send(convert(&m)).await.is_err() {
                        log.warn(&format!(
                            "{topic}: message dropped, the node's loop no longer reads it (stopping?)"
                        ));
                        break;
                    }
                }
                Err(e) => log.error(&format!("{topic}: unreadable message: {e}")),
            }
        }
    });
    Ok(())
}
