//! `--crop`: a mission or an evaluation on one cluster of buildings of a
//! large scene (a city-wide model whose ground graph would not fit).

use std::path::Path;
use std::str::FromStr;

use skyground_core::crs::{Crs, SourceFrame};
use skyground_core::graph::{GraphParams, MAX_OCCUPANCY_CELLS};
use skyground_core::io::{load_scene, write_obj};
use skyground_core::scene::{CropError, Cropped, Scene, Window, busiest_window, crop_scene};

use crate::runtime::RuntimeError;

/// What `--crop` asks for.
#[derive(Debug, Clone, PartialEq)]
pub enum CropArg {
    /// The `--crop-size` square holding the most building surface.
    Auto,
    /// The whole scene.
    None,
    /// This window, metres in the scene's local frame.
    Window(Window),
}

impl FromStr for CropArg {
    type Err = CropError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "auto" => Ok(Self::Auto),
            "none" => Ok(Self::None),
            w => w.parse().map(Self::Window),
        }
    }
}

/// The crop options of `skyground demo` and `skyground eval`.
#[derive(Debug, Clone, clap::Args)]
pub struct CropArgs {
    /// auto | none | x0,y0,x1,y1 (metres, the scene's local frame): run on the
    /// buildings whose centre lies in a window (kept whole, ground clipped).
    /// Default: auto when the scene is too large for the ground graph
    /// (about 3.5 km × 3.5 km), else none.
    #[arg(long)]
    pub crop: Option<CropArg>,
    /// Side of the automatic window, metres.
    #[arg(long, default_value_t = 250.0)]
    pub crop_size: f64,
}

/// Why `scene` is too large for the ground graph (the planner's default
/// params, config/global_planner.yaml), or `None` when it fits.
pub fn too_large(scene: &Scene) -> Option<String> {
    let (lo, hi) = scene.bounds()?;
    let size = [0, 1].map(|k| f64::from(hi[k] - lo[k]));
    let cells = GraphParams::default().occupancy_cells(size);
    (cells > MAX_OCCUPANCY_CELLS).then(|| {
        format!(
            "it spans {:.1} km × {:.1} km: its ground graph would need {cells:.1e} obstacle-grid cells (at most {MAX_OCCUPANCY_CELLS:.0e})",
            size[0] / 1000.0,
            size[1] / 1000.0
        )
    })
}

/// The crop `args` ask for on `scene` (`name` in messages); `None`: use it whole.
pub fn apply(scene: &Scene, name: &str, args: &CropArgs) -> Result<Option<Cropped>, RuntimeError> {
    let err = |e: CropError| RuntimeError::Node(format!("scene {name}: {e}"));
    let window = match &args.crop {
        Some(CropArg::None) => return Ok(None),
        Some(CropArg::Window(w)) => *w,
        Some(CropArg::Auto) => busiest_window(scene, args.crop_size).map_err(err)?,
        None => match too_large(scene) {
            None => return Ok(None),
            Some(why) => {
                let w = busiest_window(scene, args.crop_size).map_err(err)?;
                eprintln!(
                    "  scene {name}: {why}; cropping to the {} m window with the most building surface (--crop auto; --crop x0,y0,x1,y1 picks another)",
                    args.crop_size
                );
                w
            }
        },
    };
    crop_scene(scene, &window).map(Some).map_err(err)
}

/// The scene every process of a mission loads (its spec and the scene as
/// they will read it): the scene `spec` itself, or its crop (`args`; automatic
/// when the scene is too large for the ground graph) written to
/// `out`/scene.obj.
pub fn mission_scene(
    (spec, args, out): (&str, &CropArgs, &Path),
    full: Scene,
    model_crs: Option<&Crs>,
) -> Result<(String, Scene, Option<Cropped>), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let Some(c) = apply(&full, spec, args)? else {
        // Uncropped yet too large: only `--crop none` gets here.
        if let Some(why) = too_large(&full) {
            return Err(err(format!(
                "scene {spec}: {why}; run on one cluster of buildings: --crop auto (the {} m window with the most building surface, --crop-size) or --crop x0,y0,x1,y1",
                args.crop_size
            )));
        }
        return Ok((spec.to_string(), full, None));
    };
    let path = out.join("scene.obj");
    write_obj(&path, &c.scene).map_err(|e| err(e.to_string()))?;
    eprintln!(
        "  {}; written to {}",
        describe(&c, model_crs),
        path.display()
    );
    let written = path.display().to_string();
    // Read back, not c.scene: the file picks its own local frame, and the
    // survey must be in the frame vehicle_sim will load.
    let scene = load_scene(&written).map_err(|e| err(format!("scene {written}: {e}")))?;
    Ok((written, scene, Some(c)))
}

/// What a crop kept, in one line; source coordinates in the unit of the
/// scene's CRS `crs` (metres when it names none).
pub fn describe(c: &Cropped, crs: Option<&Crs>) -> String {
    let e = &c.extent;
    let frame = SourceFrame::new(c.scene.origin, crs.cloned());
    let lo = frame.to_source_xy([e.min[0], e.min[1]]);
    let hi = frame.to_source_xy([e.max[0], e.max[1]]);
    format!(
        "crop {} (local frame, m; source coordinates x {:.1}..{:.1}, y {:.1}..{:.1} {}): {} of {} buildings, ground {:.0} m × {:.0} m{}",
        c.window,
        lo[0],
        hi[0],
        lo[1],
        hi[1],
        frame.unit().symbol(),
        c.buildings.len(),
        c.buildings_total,
        e.size()[0],
        e.size()[1],
        if c.ground_filled {
            " (one ground grid: the source's ground had holes there)"
        } else {
            ""
        }
    )
}

/// The crop as report JSON (window and extent in metres in the source scene's
/// local frame, whose origin is `source_origin`, in the source CRS `crs`'s
/// coordinates and unit).
pub fn to_json(c: &Cropped, crs: Option<&Crs>) -> serde_json::Value {
    let frame = SourceFrame::new(c.scene.origin, crs.cloned());
    serde_json::json!({
        "window": c.window,
        "extent": c.extent,
        "source_origin": frame.to_source([0.0; 3]),
        "buildings_kept": c.buildings.len(),
        "buildings_total": c.buildings_total,
        "ground_filled": c.ground_filled,
        "buildings": c.buildings,
    })
}

/// The crop as a Markdown section: window, and each kept building's ids and name.
pub fn markdown(c: &Cropped) -> String {
    let mut md = format!(
        "\n## Crop\n\nwindow {} (scene's local frame), ground over {}; {} of {} buildings kept.\n\n| building | in the source | name |\n|---|---|---|\n",
        c.window,
        c.extent,
        c.buildings.len(),
        c.buildings_total
    );
    for b in &c.buildings {
        md.push_str(&format!("| {} | {} | {} |\n", b.id, b.source_id, b.name));
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_auto_none_and_windows() {
        assert_eq!("auto".parse::<CropArg>().unwrap(), CropArg::Auto);
        assert_eq!(" none".parse::<CropArg>().unwrap(), CropArg::None);
        assert_eq!(
            "0,0,250,250".parse::<CropArg>().unwrap(),
            CropArg::Window(Window::new(0.0, 0.0, 250.0, 250.0).unwrap())
        );
        assert!("everything".parse::<CropArg>().is_err());
        assert!("5,0,0,5".parse::<CropArg>().is_err());
    }

    #[test]
    fn the_reference_scene_fits_and_stays_whole() {
        let scene = skyground_core::scene::reference_scene(skyground_core::scene::REFERENCE_SEED);
        assert_eq!(too_large(&scene), None);
        let args = CropArgs {
            crop: None,
            crop_size: 250.0,
        };
        assert!(apply(&scene, "reference", &args).unwrap().is_none());
        let args = CropArgs {
            crop: Some(CropArg::Window(
                Window::new(0.0, 0.0, 100.0, 100.0).unwrap(),
            )),
            crop_size: 250.0,
        };
        let c = apply(&scene, "reference", &args).unwrap().unwrap();
        assert!(c.buildings.len() < c.buildings_total);
        assert!(!c.ground_filled);
    }

    #[test]
    fn a_scene_kilometres_wide_is_too_large() {
        use skyground_core::scene::{MeshPart, ObjectKind, SceneBuilder};
        let mut m = MeshPart::default();
        let g = m.ring(&[[0.0, 0.0], [9000.0, 0.0], [9000.0, 10_000.0]], 0.0);
        m.triangle(g[0], g[1], g[2]);
        let mut b = SceneBuilder::new([0.0; 3]);
        b.add("terrain", ObjectKind::Ground, 0, &m);
        let why = too_large(&b.finish()).unwrap();
        assert!(why.contains("9.0 km × 10.0 km"), "{why}");
        assert!(why.contains("1.4e9"), "{why}");
    }
}
