//! Why a scene cannot be cropped.

use super::Window;

/// Errors of cropping a scene or choosing its window.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CropError {
    /// The text is not `x0,y0,x1,y1`.
    #[error(
        "crop window `{text}`: expected x0,y0,x1,y1 (four numbers, metres in the scene's local frame)"
    )]
    Syntax {
        /// The text as given.
        text: String,
    },
    /// Corners not finite, or not lower-left then upper-right.
    #[error(
        "crop window ({x0}, {y0}) – ({x1}, {y1}) is empty or not finite: need x0 < x1 and y0 < y1"
    )]
    InvalidWindow {
        /// Lower-left x as given.
        x0: f64,
        /// Lower-left y as given.
        y0: f64,
        /// Upper-right x as given.
        x1: f64,
        /// Upper-right y as given.
        y1: f64,
    },
    /// The automatic window's size is not a positive length.
    #[error("crop size {size} m must be finite and > 0")]
    InvalidSize {
        /// The size as given.
        size: f64,
    },
    /// The scene has no building to crop around.
    #[error("the scene has no buildings to crop around")]
    NoBuildingsInScene,
    /// No building's centre lies in the window.
    #[error(
        "crop window {window} holds no building's centre; the scene's buildings lie within {buildings}"
    )]
    EmptyWindow {
        /// The window.
        window: Window,
        /// The xy box of the scene's building centres.
        buildings: Window,
    },
}
