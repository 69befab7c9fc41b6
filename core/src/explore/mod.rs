//! Local exploration of one region (docs/design.md step 7), TARE-style:
//! candidate viewpoints on the ground graph inside the region, scored by the
//! still-uncovered surface each would see (range, vertical field of view,
//! line of sight through known occupancy), chosen greedily with randomized
//! restarts, ordered by a small TSP, updated from incoming scans.
//!
//! - [`ExploreParams`] (`params`), [`ExploreError`] (`error`), [`SurfaceSamples`] (`surface`);
//! - `voxels`: known occupancy and line of sight; `select`: greedy cover + tour;
//! - [`Explorer`] (`explorer`); [`VoxelMerge`], [`resample`] (`voxel_merge`): voxel de-duplication;
//! - [`MergeStore`] (`store`): the merged cloud on disk as it grows; `journal`: every scan's new points between two batches; [`Inbox`] (`inbox`): every scan received, before it is merged.

mod error;
mod explorer;
mod inbox;
mod journal;
mod params;
mod select;
mod store;
mod surface;
mod voxel_merge;
mod voxels;

pub use error::ExploreError;
pub use explorer::Explorer;
pub use inbox::{INBOX_MAX_BYTES, Inbox, InboxError};
pub use journal::{JOURNAL_FILE, Journaled};
pub use params::ExploreParams;
pub use store::{KeptMerge, MergeStore, STATE_FILE, StoreError, Stored, read_store};
pub use surface::SurfaceSamples;
pub use voxel_merge::{VoxelMerge, resample};
