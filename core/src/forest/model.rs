//! The trained forest: fit, predict, vote fractions, importances, files.

use std::io::{Read, Write};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::bins::Bins;
use super::error::ForestError;
use super::params::ForestParams;
use super::tree::{Grow, Tree, grow};
use super::tree_rng;

/// Rows voted on together, tree by tree (about 60 kB of 30 features).
const VOTE_BLOCK: usize = 512;

/// A trained Random Forest over rows of `dims` features.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomForest {
    dims: usize,
    classes: Vec<u8>,
    importances: Vec<f32>,
    trees: Vec<Tree>,
}

impl RandomForest {
    /// Trains on `x` (`rows × dims`, row-major) with labels `y` (any u8
    /// codes; the distinct ones become the classes).
    pub fn fit(
        x: &[f32],
        dims: usize,
        y: &[u8],
        params: &ForestParams,
    ) -> Result<Self, ForestError> {
        params.validate()?;
        let rows = check_rows(x, dims)?;
        if rows == 0 {
            return Err(ForestError::Empty);
        }
        if y.len() != rows {
            return Err(ForestError::LabelCount {
                rows,
                labels: y.len(),
            });
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(ForestError::NonFinite {
                row: i / dims,
                feature: i % dims,
            });
        }
        let mut classes: Vec<u8> = y.to_vec();
        classes.sort_unstable();
        classes.dedup();
        let mut lookup = [0u8; 256];
        for (k, &c) in classes.iter().enumerate() {
            lookup[c as usize] = k as u8;
        }
        let yi: Vec<u8> = y.iter().map(|&c| lookup[c as usize]).collect();
        let bins = Bins::new(x, dims, params.bins);
        let mtry = params
            .max_features
            .unwrap_or_else(|| ((dims as f64).sqrt().round() as usize).max(1))
            .min(dims);
        let g = Grow {
            bins: &bins,
            y: &yi,
            classes: classes.len(),
            mtry,
            max_depth: params.max_depth,
            min_leaf: params.min_samples_leaf,
        };
        let draw = ((rows as f64 * f64::from(params.sample_fraction)).round() as usize).max(1);
        let grown: Vec<(Tree, Vec<f64>)> = (0..params.trees)
            .into_par_iter()
            .map(|t| {
                let mut rng = tree_rng(params.seed, t as u64);
                let mut sample: Vec<u32> = (0..draw).map(|_| rng.below(rows) as u32).collect();
                grow(&g, &mut sample, &mut rng)
            })
            .collect();
        let mut imp = vec![0.0f64; dims];
        for (_, ti) in &grown {
            imp.iter_mut().zip(ti).for_each(|(a, b)| *a += b);
        }
        let total: f64 = imp.iter().sum();
        let importances = imp
            .iter()
            .map(|v| if total > 0.0 { (v / total) as f32 } else { 0.0 })
            .collect();
        Ok(Self {
            dims,
            classes,
            importances,
            trees: grown.into_iter().map(|(t, _)| t).collect(),
        })
    }

    /// Features per row.
    pub fn dims(&self) -> usize {
        self.dims
    }

    /// The class codes, in the order of [`Self::predict_proba`] columns.
    pub fn classes(&self) -> &[u8] {
        &self.classes
    }

    /// Mean Gini decrease per feature, summing to 1.
    pub fn importances(&self) -> &[f32] {
        &self.importances
    }

    /// Number of trees.
    pub fn tree_count(&self) -> usize {
        self.trees.len()
    }

    /// Total nodes of all trees (model size).
    pub fn node_count(&self) -> usize {
        self.trees.iter().map(|t| t.feature.len()).sum()
    }

    /// The majority-vote class code of each row of `rows` (row-major).
    pub fn predict(&self, rows: &[f32]) -> Result<Vec<u8>, ForestError> {
        let proba = self.predict_proba(rows)?;
        let c = self.classes.len();
        Ok(proba
            .chunks(c)
            .map(|p| {
                let mut best = 0;
                for k in 1..c {
                    if p[k] > p[best] {
                        best = k;
                    }
                }
                self.classes[best]
            })
            .collect())
    }

    /// Share of trees voting for each class, `rows × classes().len()`.
    pub fn predict_proba(&self, rows: &[f32]) -> Result<Vec<f32>, ForestError> {
        if !rows.len().is_multiple_of(self.dims) {
            return Err(ForestError::Dims {
                expected: self.dims,
                got: rows.len(),
            });
        }
        let c = self.classes.len();
        let share = 1.0 / self.trees.len() as f32;
        let mut out = vec![0.0f32; rows.len() / self.dims * c];
        // Tree by tree over a block of rows: one tree's nodes stay in cache
        // while the block goes through it; row by row, every row walked all
        // 48 trees (3.8 MB of nodes) through the cache. Each row still adds
        // its votes in tree order, so the sums are the same to the bit.
        out.par_chunks_mut(c * VOTE_BLOCK)
            .zip(rows.par_chunks(self.dims * VOTE_BLOCK))
            .for_each(|(votes, block)| {
                for t in &self.trees {
                    for (v, row) in votes.chunks_mut(c).zip(block.chunks(self.dims)) {
                        v[t.leaf_class(row) as usize] += share;
                    }
                }
            });
        Ok(out)
    }

    /// Writes the forest as JSON.
    pub fn to_writer<W: Write>(&self, w: W) -> Result<(), ForestError> {
        Ok(serde_json::to_writer(w, self)?)
    }

    /// Reads a forest written by [`Self::to_writer`] and checks it.
    pub fn from_reader<R: Read>(r: R) -> Result<Self, ForestError> {
        let f: Self = serde_json::from_reader(r)?;
        f.check()?;
        Ok(f)
    }

    /// Checks a deserialized forest so prediction cannot index out of range.
    pub fn check(&self) -> Result<(), ForestError> {
        if self.dims == 0 || self.classes.is_empty() || self.trees.is_empty() {
            return Err(ForestError::Corrupt("no features, classes or trees".into()));
        }
        if self.importances.len() != self.dims {
            return Err(ForestError::Corrupt("importances do not match dims".into()));
        }
        for (i, t) in self.trees.iter().enumerate() {
            t.check(self.dims, self.classes.len())
                .map_err(|e| ForestError::Corrupt(format!("tree {i}: {e}")))?;
        }
        Ok(())
    }
}

fn check_rows(x: &[f32], dims: usize) -> Result<usize, ForestError> {
    if dims == 0 || !x.len().is_multiple_of(dims) {
        return Err(ForestError::Shape {
            values: x.len(),
            dims,
        });
    }
    Ok(x.len() / dims)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two noisy interleaved spirals plus a third class on a ring: not
    /// separable by one axis-aligned split.
    fn data(n: usize, seed: u64) -> (Vec<f32>, Vec<u8>) {
        let mut rng = tree_rng(seed, 0);
        let mut u = || rng.next_u64() as f64 / u64::MAX as f64;
        let (mut x, mut y) = (Vec::new(), Vec::new());
        for i in 0..n {
            let class = (i % 3) as u8;
            let t = u() * 3.0 * std::f64::consts::PI;
            let (px, py) = match class {
                0 => (t * t.cos(), t * t.sin()),
                1 => (-t * t.cos(), -t * t.sin()),
                _ => (11.0 * t.cos(), 11.0 * t.sin()),
            };
            x.extend([(px + 0.3 * u()) as f32, (py + 0.3 * u()) as f32, u() as f32]);
            y.push([2u8, 5, 6][class as usize]);
        }
        (x, y)
    }

    #[test]
    fn learns_spirals_and_is_deterministic() {
        let (x, y) = data(6000, 1);
        let p = ForestParams {
            trees: 16,
            ..ForestParams::default()
        };
        let f = RandomForest::fit(&x, 3, &y, &p).unwrap();
        assert_eq!(f.classes(), &[2, 5, 6]);
        let (xt, yt) = data(3000, 2);
        let pred = f.predict(&xt).unwrap();
        let acc = pred.iter().zip(&yt).filter(|(a, b)| a == b).count() as f64 / yt.len() as f64;
        assert!(acc > 0.95, "accuracy {acc}");
        // The noise feature carries little weight.
        let imp = f.importances();
        assert!(
            imp[2] < 0.1 && (imp.iter().sum::<f32>() - 1.0).abs() < 1e-4,
            "{imp:?}"
        );
        let again = RandomForest::fit(&x, 3, &y, &p).unwrap();
        assert_eq!(f, again);
        let mut buf = Vec::new();
        f.to_writer(&mut buf).unwrap();
        let back = RandomForest::from_reader(buf.as_slice()).unwrap();
        assert_eq!(back.predict(&xt).unwrap(), pred);
        let proba = f.predict_proba(&xt[..3]).unwrap();
        assert!((proba.iter().sum::<f32>() - 1.0).abs() < 1e-5);
    }

    #[test]
    fn votes_by_blocks_of_rows_equal_each_row_through_every_tree() {
        let (x, y) = data(3000, 3);
        let p = ForestParams {
            trees: 12,
            ..ForestParams::default()
        };
        let f = RandomForest::fit(&x, 3, &y, &p).unwrap();
        // Two whole blocks and a part of one.
        let (xt, _) = data(2 * VOTE_BLOCK + 37, 4);
        let got = f.predict_proba(&xt).unwrap();
        let share = 1.0 / f.tree_count() as f32;
        for (row, votes) in xt.chunks(3).zip(got.chunks(3)) {
            let mut want = [0.0f32; 3];
            for t in &f.trees {
                want[t.leaf_class(row) as usize] += share;
            }
            assert_eq!(votes, want);
        }
    }

    #[test]
    fn bad_input_is_typed() {
        let p = ForestParams::default();
        assert!(matches!(
            RandomForest::fit(&[], 3, &[], &p),
            Err(ForestError::Empty)
        ));
        assert!(matches!(
            RandomForest::fit(&[1.0; 5], 3, &[1], &p),
            Err(ForestError::Shape { .. })
        ));
        assert!(matches!(
            RandomForest::fit(&[1.0; 6], 3, &[1], &p),
            Err(ForestError::LabelCount { .. })
        ));
        assert!(matches!(
            RandomForest::fit(&[1.0, f32::NAN, 0.0], 3, &[1], &p),
            Err(ForestError::NonFinite { row: 0, feature: 1 })
        ));
        let bad = ForestParams {
            trees: 0,
            ..p.clone()
        };
        assert!(matches!(
            RandomForest::fit(&[1.0; 3], 3, &[1], &bad),
            Err(ForestError::Param(_))
        ));
        // One class, one row: a valid (trivial) forest.
        let f = RandomForest::fit(&[1.0; 3], 3, &[6], &p).unwrap();
        assert_eq!(f.predict(&[0.0; 6]).unwrap(), vec![6, 6]);
        assert!(matches!(
            f.predict(&[0.0; 4]),
            Err(ForestError::Dims { .. })
        ));
        assert!(RandomForest::from_reader(&b"{\"dims\":1}"[..]).is_err());
    }
}
