//! Accuracy of a classification against reference labels: confusion
//! matrix, per-class precision / recall / F1, overall accuracy.

use serde::{Deserialize, Serialize};

use super::error::ClassifyError;
use crate::cloud::ColumnLength;
use crate::cloud::class::{BUILDING, GROUND, UNCLASSIFIED, VEGETATION, fold};

/// Precision, recall and F1 of one class.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClassMetrics {
    /// LAS code.
    pub class: u8,
    /// Reference points of this class.
    pub support: u64,
    /// Points predicted as this class.
    pub predicted: u64,
    /// Correct / predicted (0 when nothing was predicted).
    pub precision: f64,
    /// Correct / support (0 when the class is absent).
    pub recall: f64,
    /// Harmonic mean of precision and recall.
    pub f1: f64,
}

/// A classification compared with its reference, both folded to
/// unclassified / ground / vegetation / building.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClassReport {
    /// Row / column order of `confusion`.
    pub classes: Vec<u8>,
    /// `confusion[truth][predicted]` point counts.
    pub confusion: Vec<Vec<u64>>,
    /// One entry per class.
    pub per_class: Vec<ClassMetrics>,
    /// Share of points whose folded class matches.
    pub overall_accuracy: f64,
    /// Points compared.
    pub points: u64,
}

/// Producer classes a classification is scored on: ground, vegetation
/// (3/4/5) and building. The rest (unclassified, water, wires, noise) say
/// nothing about which of the three a point is.
pub fn is_scored(truth: u8) -> bool {
    (GROUND..=BUILDING).contains(&truth)
}

impl ClassReport {
    /// [`Self::new`] over the points whose producer class [`is_scored`].
    pub fn on_scored(truth: &[u8], predicted: &[u8]) -> Result<Self, ClassifyError> {
        let (t, p): (Vec<u8>, Vec<u8>) = truth
            .iter()
            .zip(predicted)
            .filter(|(t, _)| is_scored(**t))
            .map(|(t, p)| (*t, *p))
            .unzip();
        Self::new(&t, &p)
    }

    /// Compares `predicted` with `truth` (producer LAS codes, folded).
    pub fn new(truth: &[u8], predicted: &[u8]) -> Result<Self, ClassifyError> {
        ColumnLength::check("predicted labels", truth.len(), predicted.len())?;
        let classes = vec![UNCLASSIFIED, GROUND, VEGETATION, BUILDING];
        let at = |c: u8| classes.iter().position(|&k| k == fold(c)).unwrap_or(0);
        let mut confusion = vec![vec![0u64; classes.len()]; classes.len()];
        for (&t, &p) in truth.iter().zip(predicted) {
            confusion[at(t)][at(p)] += 1;
        }
        let ratio = |a: u64, b: u64| if b == 0 { 0.0 } else { a as f64 / b as f64 };
        let per_class = (0..classes.len())
            .map(|k| {
                let tp = confusion[k][k];
                let support: u64 = confusion[k].iter().sum();
                let predicted: u64 = confusion.iter().map(|r| r[k]).sum();
                let (precision, recall) = (ratio(tp, predicted), ratio(tp, support));
                let f1 = if precision + recall > 0.0 {
                    2.0 * precision * recall / (precision + recall)
                } else {
                    0.0
                };
                ClassMetrics {
                    class: classes[k],
                    support,
                    predicted,
                    precision,
                    recall,
                    f1,
                }
            })
            .collect();
        let correct: u64 = (0..classes.len()).map(|k| confusion[k][k]).sum();
        Ok(Self {
            overall_accuracy: ratio(correct, truth.len() as u64),
            points: truth.len() as u64,
            classes,
            confusion,
            per_class,
        })
    }

    /// Metrics of LAS class `class` (folded).
    pub fn class(&self, class: u8) -> Option<&ClassMetrics> {
        self.per_class.iter().find(|m| m.class == fold(class))
    }

    /// A plain-text table: confusion matrix and per-class figures.
    pub fn table(&self) -> String {
        let name = |c: u8| match c {
            GROUND => "ground",
            VEGETATION => "vegetation",
            BUILDING => "building",
            _ => "other",
        };
        let mut s = String::from("truth \\ predicted");
        for &c in &self.classes {
            s += &format!("{:>11}", name(c));
        }
        s += "    precision recall     F1  support\n";
        for (k, row) in self.confusion.iter().enumerate() {
            let m = &self.per_class[k];
            s += &format!("{:<17}", name(self.classes[k]));
            for v in row {
                s += &format!("{v:>11}");
            }
            s += &format!(
                "    {:>9.4} {:>6.4} {:>6.4} {:>8}\n",
                m.precision, m.recall, m.f1, m.support
            );
        }
        s += &format!(
            "overall accuracy {:.4} over {} points\n",
            self.overall_accuracy, self.points
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_fold_and_mismatch() {
        // Producer codes 3 and 4 fold into vegetation; 14 into other.
        let truth = [6, 6, 6, 6, 3, 4, 5, 2, 14];
        let pred = [6, 6, 6, 5, 5, 6, 5, 2, 6];
        let r = ClassReport::new(&truth, &pred).unwrap();
        let b = r.class(BUILDING).unwrap();
        assert_eq!((b.support, b.predicted), (4, 5));
        assert!((b.precision - 3.0 / 5.0).abs() < 1e-12 && (b.recall - 0.75).abs() < 1e-12);
        let v = r.class(4).unwrap();
        assert_eq!(v.support, 3);
        assert!((v.recall - 2.0 / 3.0).abs() < 1e-12);
        assert!((r.overall_accuracy - 6.0 / 9.0).abs() < 1e-12);
        assert_eq!(r.confusion.iter().flatten().sum::<u64>(), 9);
        assert!(r.table().contains("building"));
        assert!(ClassReport::new(&truth, &pred[..3]).is_err());
        let empty = ClassReport::new(&[], &[]).unwrap();
        assert_eq!(empty.overall_accuracy, 0.0);
    }
}
