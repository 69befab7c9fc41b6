//! A publish that does not return says so while it waits: a DDS writer that
//! never admits a sample would otherwise stop a node without a word.

use std::future::Future;
use std::time::Duration;

/// How long a publish may wait before the node says it is stuck.
pub const PUBLISH_WAIT_SAID_EVERY: Duration = Duration::from_secs(10);

/// Awaits `fut`, calling `on_wait(n)` after each `every` it has not finished
/// (n = 1, 2, …); its output is returned unchanged (nothing is cancelled).
pub async fn watched<F: Future>(
    fut: F,
    every: Duration,
    mut on_wait: impl FnMut(u32),
) -> F::Output {
    tokio::pin!(fut);
    let mut waited = 0u32;
    loop {
        tokio::select! {
            out = &mut fut => return out,
            () = tokio::time::sleep(every) => {
                waited += 1;
                on_wait(waited);
            }
        }
    }
}

/// [`watched`] with the node's log: "publishing on TOPIC has waited N s".
pub async fn publish_watched<F: Future>(log: &super::Logger, topic: &str, fut: F) -> F::Output {
    let every = PUBLISH_WAIT_SAID_EVERY;
    watched(fut, every, |n| {
        log.error(&format!(
            "publishing on {topic} has waited {} s: the DDS writer admits no sample (is the participant's event loop stuck?)",
            u64::from(n) * every.as_secs()
        ));
    })
    .await
}

/// [`publish_watched`], then [`super::Logger::sent`]: a publish that fails
/// is logged too; true when it was sent.
pub async fn publish_logged<E, F>(log: &super::Logger, topic: &str, fut: F) -> bool
where
    E: std::fmt::Debug,
    F: Future<Output = Result<(), E>>,
{
    let r = publish_watched(log, topic, fut).await;
    log.sent(topic, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn a_stuck_publish_is_said_and_a_quick_one_is_not() {
        let every = Duration::from_millis(20);
        let mut said = Vec::new();
        let out = watched(async { 7 }, every, |n| said.push(n)).await;
        assert_eq!((out, said.len()), (7, 0));
        // Done after about three periods: said twice or three times, in order.
        let slow = async {
            tokio::time::sleep(Duration::from_millis(70)).await;
            8
        };
        let out = watched(slow, every, |n| said.push(n)).await;
        assert_eq!(out, 8);
        assert!((2..=3).contains(&said.len()), "{said:?}");
        assert_eq!(said[..2], [1, 2]);
        // Never done: still said, every period.
        let never = std::future::pending::<()>();
        let timed = tokio::time::timeout(
            Duration::from_millis(110),
            watched(never, every, |n| said.push(n)),
        )
        .await;
        assert!(timed.is_err());
        assert!(said.len() >= 5, "{said:?}");
    }
}
