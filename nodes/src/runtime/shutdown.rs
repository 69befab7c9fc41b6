//! Orderly stop on SIGINT / SIGTERM: a watch flag every node loop selects on.

use tokio::sync::watch;

/// A handle that resolves when the process is asked to stop.
#[derive(Clone)]
pub struct Shutdown {
    rx: watch::Receiver<bool>,
    tx: std::sync::Arc<watch::Sender<bool>>,
}

impl Shutdown {
    /// Installs the SIGINT/SIGTERM handlers (must run inside a tokio runtime).
    pub fn install() -> Self {
        let (tx, rx) = watch::channel(false);
        let tx = std::sync::Arc::new(tx);
        let t = tx.clone();
        tokio::spawn(async move {
            wait_for_signal().await;
            let _ = t.send(true);
        });
        Self { rx, tx }
    }

    /// Asks every holder to stop (e.g. a node that finished its work).
    pub fn trigger(&self) {
        let _ = self.tx.send(true);
    }

    /// True once a stop was requested.
    pub fn requested(&self) -> bool {
        *self.rx.borrow()
    }

    /// What `next` gives, or `None` once a stop is requested first.
    pub async fn or<T>(&self, next: impl Future<Output = Option<T>>) -> Option<T> {
        tokio::select! {
            r = next => r,
            _ = self.wait() => None,
        }
    }

    /// Resolves when a stop is requested.
    pub async fn wait(&self) {
        let mut rx = self.rx.clone();
        while !*rx.borrow_and_update() {
            if rx.changed().await.is_err() {
                return;
            }
        }
    }
}

async fn wait_for_signal() {
    use tokio::signal::unix::{SignalKind, signal};
    match (
        signal(SignalKind::interrupt()),
        signal(SignalKind::terminate()),
    ) {
        (Ok(mut int), Ok(mut term)) => {
            tokio::select! {
                _ = int.recv() => {}
                _ = term.recv() => {}
            }
        }
        _ => {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}
