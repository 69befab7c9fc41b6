//! Step 1 end to end: the Cloth Simulation Filter finds the ground and the
//! height above it, the forest tells vegetation from buildings.

use std::time::Instant;

use super::error::ClassifyError;
use super::grade::AtGrade;
use super::lone::{REACH_CELLS, lone_ground};
use super::model::Model;
use super::pipeline::classify_at;
use crate::cloud::{Cloud, ColumnLength, class};
use crate::features::Echoes;
use crate::ground::{CsfParams, GroundSplit, csf};

/// A ground filter and a trained model, ready for clouds.
#[derive(Debug, Clone)]
pub struct SceneClassifier {
    csf: CsfParams,
    model: Model,
}

/// One classified cloud.
#[derive(Debug, Clone)]
pub struct Classified {
    /// LAS class per point (2 ground, 5 vegetation, 6 building, 1 other;
    /// see [`SceneClassifier::classify_cloud`] for the producer's classes kept).
    pub labels: Vec<u8>,
    /// The ground filter's result: its verdict and height above the terrain
    /// per point, the terrain model, the density and its parameters as used.
    pub ground: GroundSplit,
    /// Seconds in the ground filter.
    pub seconds_csf: f64,
    /// Seconds in features and forest.
    pub seconds_classify: f64,
    /// Points the ground filter left standing that are ground after all:
    /// building surfaces that continue the terrain (now ground, or bridge
    /// deck) and points the forest calls ground; ground ones are ground in
    /// `ground.is_ground` too.
    pub at_grade: AtGrade,
}

impl Classified {
    /// Both stages' seconds.
    pub fn seconds_total(&self) -> f64 {
        self.seconds_csf + self.seconds_classify
    }

    /// Points per class, by class name.
    pub fn counts(&self) -> std::collections::BTreeMap<&'static str, usize> {
        let mut out = std::collections::BTreeMap::new();
        for &l in &self.labels {
            let name = match l {
                class::GROUND => "ground",
                class::VEGETATION => "vegetation",
                class::BUILDING => "building",
                class::BRIDGE_DECK => "bridge deck",
                _ => "other",
            };
            *out.entry(name).or_insert(0) += 1;
        }
        out
    }

    /// What the user is told about points relabelled after the forest:
    /// ground the filter raised, terrain read as roofs.
    pub fn messages(&self) -> impl Iterator<Item = String> {
        [self.ground.raised.message(), self.at_grade.message()]
            .into_iter()
            .flatten()
    }

    /// The counts as one line.
    pub fn summary(&self) -> String {
        self.counts()
            .iter()
            .map(|(k, v)| format!("{k} {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl SceneClassifier {
    /// Checks both halves before any cloud arrives.
    pub fn new(csf: CsfParams, model: Model) -> Result<Self, ClassifyError> {
        csf.validate()?;
        model.check()?;
        Ok(Self { csf, model })
    }

    /// Classifies a cloud, using its echo columns when it has them.
    ///
    /// When the cloud carries a producer's classes, its noise
    /// ([`class::is_noise`]) is left out of the ground filter and the
    /// features (not ground, height above the terrain model), and every
    /// point whose class says more than ours could
    /// (not [`class::replaced_by_classifier`]: water, bridges, wires,
    /// noise, producers' own codes) keeps it.
    pub fn classify_cloud(&self, cloud: &Cloud) -> Result<Classified, ClassifyError> {
        let Some(producer) = cloud.label.as_deref() else {
            return self.classify(&cloud.xyz, echoes_of(cloud));
        };
        ColumnLength::check("label", cloud.len(), producer.len())?;
        let used: Vec<usize> = (0..cloud.len())
            .filter(|&i| !class::is_noise(producer[i]))
            .collect();
        let mut c = if used.len() == cloud.len() {
            self.classify(&cloud.xyz, echoes_of(cloud))?
        } else {
            let sub = cloud.subset(&used);
            let part = self.classify(&sub.xyz, echoes_of(&sub))?;
            spread(part, &used, &cloud.xyz)
        };
        for (l, &p) in c.labels.iter_mut().zip(producer) {
            if !class::replaced_by_classifier(p) {
                *l = p;
            }
        }
        Ok(c)
    }

    /// The model in use.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// What a user is told when `cloud` has no echo information (no pulse
    /// gave two returns); `None` when it has.
    pub fn echo_note(&self, cloud: &Cloud) -> Option<&'static str> {
        if cloud.echoes().is_some() {
            None
        } else if self.model.forest_without_echoes.is_some() {
            Some(
                "no pulse in the cloud gave two returns: classified by the model's forest trained without echoes",
            )
        } else {
            Some(
                "no pulse in the cloud gave two returns and the model has no forest trained without echoes (an older model file): its forest expects echoes, so crowns may be called roofs; retrain it with `skyground train`",
            )
        }
    }

    /// Classifies `xyz` (local frame) with its echoes, when known.
    pub fn classify(
        &self,
        xyz: &[[f32; 3]],
        echoes: Option<Echoes<'_>>,
    ) -> Result<Classified, ClassifyError> {
        let t0 = Instant::now();
        let mut ground = csf(xyz, &self.csf)?;
        let seconds_csf = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        // Points the filter skipped (non-finite) have a NaN height: keep them out of the features.
        if let Some(index) = ground.hag.iter().position(|h| !h.is_finite()) {
            return Err(ClassifyError::NonFinite { index });
        }
        let spacing = ground.density.spacing_m;
        let (mut labels, mut at_grade) = classify_at(
            xyz,
            &ground.hag,
            &ground.is_ground,
            echoes,
            &self.model,
            spacing,
        )?;
        let reach = REACH_CELLS * ground.params.cloth_resolution_for(&ground.density);
        let radius = self.model.feature_params.radius_large_m;
        at_grade.lone_ground = lone_ground(xyz, &mut labels, radius, reach);
        // Terrain the cloth hung below is ground for every later step (the
        // ground report, the ground graph), though its height above the
        // terrain model stays as the cloth measured it.
        for (g, &l) in ground.is_ground.iter_mut().zip(&labels) {
            *g |= l == class::GROUND;
        }
        Ok(Classified {
            labels,
            ground,
            seconds_csf,
            seconds_classify: t1.elapsed().as_secs_f64(),
            at_grade,
        })
    }
}

/// `part`, classified from the points `used` of `xyz`, spread back over
/// all of `xyz`: the points left out are unclassified (1) and not ground,
/// with their height above `part`'s terrain model.
fn spread(part: Classified, used: &[usize], xyz: &[[f32; 3]]) -> Classified {
    let n = xyz.len();
    let mut labels = vec![class::UNCLASSIFIED; n];
    let mut is_ground = vec![false; n];
    let mut hag = vec![f32::NAN; n];
    for (k, &i) in used.iter().enumerate() {
        labels[i] = part.labels[k];
        is_ground[i] = part.ground.is_ground[k];
        hag[i] = part.ground.hag[k];
    }
    // `classify` refuses a non-finite height, so NaN marks exactly the
    // points left out.
    let dtm = &part.ground.dtm;
    for (h, p) in hag.iter_mut().zip(xyz).filter(|(h, _)| h.is_nan()) {
        *h = p[2] - dtm.height_at(p[0], p[1]);
    }
    Classified {
        labels,
        ground: GroundSplit {
            is_ground,
            hag,
            ..part.ground
        },
        ..part
    }
}

/// The echo columns of `cloud` as feature input, when they say something.
pub fn echoes_of(cloud: &Cloud) -> Option<Echoes<'_>> {
    cloud.echoes().map(|(rn, nr)| Echoes {
        return_number: rn,
        number_of_returns: nr,
    })
}

/// Ground vs non-ground against reference labels, ISPRS-style (the CSF
/// paper's measures): bare earth against objects, low vegetation apart.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GroundReport {
    /// Points compared.
    pub points: usize,
    /// Which points were compared: "bare earth (2) vs objects (4-6), low
    /// vegetation (3) left out" (unclassified, water, noise and bridges say
    /// nothing about the ground filter) or, when the reference has no class
    /// 3–6 point (ground / unclassified only, e.g. Autzen), "producer ground
    /// only": its other points are not known to be off the ground.
    pub scope: &'static str,
    /// Misclassified / compared (type I alone for "producer ground only").
    pub total_error: f64,
    /// Type I: bare earth called non-ground / reference bare earth.
    pub type_i: f64,
    /// Type II: objects called ground / reference objects; `None` when the
    /// reference names no object point.
    pub type_ii: Option<f64>,
    /// Cohen's kappa of the two-class agreement; `None` with `type_ii`.
    pub kappa: Option<f64>,
    /// The total error with low vegetation (3) counted as object; `None`
    /// with `type_ii`.
    pub total_error_with_low_vegetation: Option<f64>,
    /// Reference low-vegetation (3) points.
    pub low_vegetation_points: usize,
    /// Share of them called ground; `None` when there are none.
    pub low_vegetation_called_ground: Option<f64>,
}

impl GroundReport {
    /// Compares the filter's ground flags with LAS labels: bare earth (2)
    /// against objects (4–6), low vegetation (3) apart, or the producer's
    /// ground alone when it labels no class 3–6 point.
    pub fn new(truth: &[u8], is_ground: &[bool]) -> Result<Self, ClassifyError> {
        ColumnLength::check("ground flags", truth.len(), is_ground.len())?;
        if truth.is_empty() {
            return Err(ClassifyError::Empty);
        }
        let labelled = truth.iter().any(|t| (3..=6).contains(t));
        let scored = |t: u8| {
            if labelled {
                t == class::GROUND || (4..=6).contains(&t)
            } else {
                t == class::GROUND
            }
        };
        let (mut a, mut b, mut c, mut d) = (0f64, 0f64, 0f64, 0f64);
        let (mut low, mut low_ground) = (0usize, 0usize);
        for (&t, &g) in truth.iter().zip(is_ground) {
            if t == class::LOW_VEGETATION {
                low += 1;
                low_ground += usize::from(g);
            }
            if !scored(t) {
                continue;
            }
            match (t == class::GROUND, g) {
                (true, true) => a += 1.0,
                (true, false) => b += 1.0,
                (false, true) => c += 1.0,
                (false, false) => d += 1.0,
            }
        }
        let n = a + b + c + d;
        if n == 0.0 {
            return Err(ClassifyError::Empty);
        }
        let ratio = |x: f64, y: f64| if y > 0.0 { x / y } else { 0.0 };
        let po = (a + d) / n;
        let pe = ((a + b) * (a + c) + (c + d) * (b + d)) / (n * n);
        let kappa = if pe < 1.0 {
            (po - pe) / (1.0 - pe)
        } else {
            1.0
        };
        let with_low = (b + c + low_ground as f64) / (n + low as f64);
        Ok(Self {
            points: n as usize,
            scope: if labelled {
                "bare earth (2) vs objects (4-6), low vegetation (3) left out"
            } else {
                "producer ground only"
            },
            total_error: (b + c) / n,
            type_i: ratio(b, a + b),
            type_ii: labelled.then(|| ratio(c, c + d)),
            kappa: labelled.then_some(kappa),
            total_error_with_low_vegetation: labelled.then_some(with_low),
            low_vegetation_points: low,
            low_vegetation_called_ground: (low > 0).then(|| low_ground as f64 / low as f64),
        })
    }

    /// One line: total error, type I, type II and kappa where known.
    pub fn line(&self) -> String {
        let mut s = format!(
            "ground ({}, {} points): total error {:.2} %, type I {:.2} %",
            self.scope,
            self.points,
            self.total_error * 100.0,
            self.type_i * 100.0
        );
        match (self.type_ii, self.kappa) {
            (Some(t2), Some(k)) => s += &format!(", type II {:.2} %, kappa {k:.3}", t2 * 100.0),
            _ => s += " (no non-ground reference: type II unknown)",
        }
        if let (Some(e), Some(g)) = (
            self.total_error_with_low_vegetation,
            self.low_vegetation_called_ground,
        ) {
            s += &format!(
                "; with low vegetation as object {:.2} % ({:.1} % of its {} points called ground)",
                e * 100.0,
                g * 100.0,
                self.low_vegetation_points
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ground_report_counts_both_error_types() {
        let truth = [2, 2, 2, 2, 6, 6, 6, 6];
        let flags = [true, true, true, false, true, false, false, false];
        let r = GroundReport::new(&truth, &flags).unwrap();
        assert_eq!(r.total_error, 0.25);
        assert_eq!(r.type_i, 0.25);
        assert_eq!(r.type_ii, Some(0.25));
        assert!((r.kappa.unwrap_or(0.0) - 0.5).abs() < 1e-12);
        assert!(r.line().contains("type II 25.00 %"));
        assert!(GroundReport::new(&truth, &flags[..3]).is_err());
        // Water (9) and unclassified (1) are left out when classes 3–6
        // exist; low vegetation (3) is apart: only in the second total.
        let truth = [2, 2, 6, 6, 9, 1, 3, 3];
        let flags = [true, false, false, false, true, true, true, false];
        let r = GroundReport::new(&truth, &flags).unwrap();
        assert_eq!((r.points, r.total_error), (4, 0.25));
        assert_eq!(r.total_error_with_low_vegetation, Some(2.0 / 6.0));
        assert_eq!(
            (r.low_vegetation_points, r.low_vegetation_called_ground),
            (2, Some(0.5))
        );
        // Ground / unclassified only (Autzen): unclassified is not known to
        // be off the ground, so only the producer's ground is judged.
        let r = GroundReport::new(&[2, 2, 1, 1], &[true, false, true, false]).unwrap();
        assert_eq!((r.points, r.scope), (2, "producer ground only"));
        assert_eq!((r.type_i, r.total_error), (0.5, 0.5));
        assert_eq!((r.type_ii, r.kappa), (None, None));
        assert!(r.line().contains("type II unknown"));
        assert!(GroundReport::new(&[1, 1], &[true, false]).is_err());
    }
}
