//! SVG and PNG plots of a sweep (plotters with an embedded DejaVu font: no system font
//! library is needed).
//!
//! - `speed_vs_error_{2d,3d}`: particles/s (all threads) against 1 − M, log scales. With the
//!   scale tier: one marker per method at default parameters, its speed from the scale tier
//!   ([`scale_markers`]); without it (the default, and `--quick`): one marker per method and
//!   parameter value, pooled over the scenes of that dimension. 1 − M is pooled over the
//!   fixture scenes either way.
//! - `scale_{2d,3d}`: seconds against |P|, log-log, one line per method (the scale tier).
//!
//! Every method has one colour and one marker shape in every plot ([`style_of`]). In the
//! speed/error charts only the markers of the default parameters are labelled (with the
//! method's name, placed clear of the other markers and labels); the other parameter values
//! are small outlines of the method's marker.
//! - `features_<scene>`: for 2D scenes, the feature class of each exact boundary particle
//!   (thesis Sec. 2.6, Fig. 15 colours).
//! - `depth_{2d,3d}`: false positives and time against depth for `ia` and `ge` (JCP Fig. 7,
//!   thesis Fig. 27).
//! - `labels_<scene>`: for each 2D scene, each method's labels with false positives (red) and
//!   false negatives (blue) highlighted (JCP Fig. 8).
//! - `fail_<method>`: for each method without a certificate, its worst scene (lowest M) with
//!   false negatives (blue) and false positives (red); a 3D scene is drawn as the 2r-thick
//!   slab holding the most misses ([`FailurePicture::slab`]) beside the projection of every
//!   particle along the slab's axis with all misses on top.
//! - `domain_<scene>`: for each scene with a domain, the exact labels in it: fluid interior
//!   (by phase) and free surface, interface particles, walls in a neutral grey, solid
//!   half-spaces as lines at their bounds (hatched side solid) and periodic bounds dashed; a
//!   3D scene as the slab of half-width r/2 across the middle of the fluid along y, in the
//!   x–z plane.

use crate::failures::FailurePicture;
use crate::scale::ScaleOutcome;
use crate::{DomainPicture, Outcome, Picture, Row};
use boundary::Confusion;
use plotters::coord::Shift;
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};
use std::path::{Path, PathBuf};

/// 1 − M below this is drawn at this value (log scale; M = 1 is a perfect score).
pub const ERROR_FLOOR: f64 = 1e-5;

/// The shape of a method's marker.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A disc.
    Circle,
    /// A square.
    Square,
    /// A triangle pointing up.
    TriangleUp,
    /// A triangle pointing down.
    TriangleDown,
    /// A square on its corner.
    Diamond,
    /// An ×.
    Cross,
    /// A +.
    Plus,
}

/// How a method is drawn in every plot of the sweep: its colour and the shape of its marker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodStyle {
    /// The colour of the method's markers and lines.
    pub colour: RGBColor,
    /// The shape of its markers.
    pub shape: Shape,
}

/// One fixed style per method, the same in every plot and whatever the methods a run
/// selects: no two methods share both colour and shape.
const STYLES: [(&str, RGBColor, Shape); 12] = [
    ("exact", RGBColor(0, 0, 0), Shape::Circle),
    ("dilts", RGBColor(127, 127, 127), Shape::Square),
    ("ia", RGBColor(31, 119, 180), Shape::TriangleUp),
    ("ge", RGBColor(23, 190, 207), Shape::TriangleDown),
    ("marrone", RGBColor(214, 39, 40), Shape::Diamond),
    ("muller", RGBColor(255, 127, 14), Shape::Circle),
    ("divr", RGBColor(44, 160, 44), Shape::Square),
    ("asymmetry", RGBColor(148, 103, 189), Shape::TriangleUp),
    ("randles", RGBColor(140, 86, 75), Shape::TriangleDown),
    ("lnm", RGBColor(227, 119, 194), Shape::Diamond),
    ("hpr", RGBColor(188, 189, 34), Shape::Plus),
    ("svm", RGBColor(0, 0, 128), Shape::Cross),
];

/// The style of `method` from a fixed table; a method missing from it is dark grey, with a
/// shape taken from its name.
pub fn style_of(method: &str) -> MethodStyle {
    match STYLES.iter().find(|(name, _, _)| *name == method) {
        Some(&(_, colour, shape)) => MethodStyle { colour, shape },
        None => {
            const SHAPES: [Shape; 7] = [
                Shape::Circle,
                Shape::Square,
                Shape::TriangleUp,
                Shape::TriangleDown,
                Shape::Diamond,
                Shape::Cross,
                Shape::Plus,
            ];
            let k = method.bytes().map(usize::from).sum::<usize>() % SHAPES.len();
            MethodStyle {
                colour: RGBColor(70, 70, 70),
                shape: SHAPES[k],
            }
        }
    }
}

/// The marker of `style` at `at`, `size` pixels from its centre to its edge: filled, or as
/// an outline (a method's runs at other than its default parameters).
fn marker<C>(at: C, style: MethodStyle, size: i32, filled: bool) -> Glyph<C> {
    Glyph {
        at,
        style,
        size,
        filled,
    }
}

/// A method's marker: one point of the chart, drawn in pixels around it.
#[derive(Debug, Clone, Copy)]
struct Glyph<C> {
    at: C,
    style: MethodStyle,
    size: i32,
    filled: bool,
}

impl<'a, C> PointCollection<'a, C> for &'a Glyph<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for Glyph<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut points: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((x, y)) = points.next() else {
            return Ok(());
        };
        let (s, h) = (self.size, self.size * 7 / 8);
        let colour = self.style.colour;
        let outline = colour.stroke_width(2);
        let line = colour.stroke_width(if self.filled { 3 } else { 2 });
        let at = |pts: &[(i32, i32)]| pts.iter().map(|&(dx, dy)| (x + dx, y + dy)).collect();
        let polygon = |backend: &mut DB, pts: &[(i32, i32)]| {
            if self.filled {
                backend.fill_polygon(at(pts), &colour.filled())
            } else {
                let mut closed: Vec<BackendCoord> = at(pts);
                closed.push(closed[0]);
                backend.draw_path(closed, &outline)
            }
        };
        match self.style.shape {
            Shape::Circle => backend.draw_circle((x, y), s as u32, &outline, self.filled),
            Shape::Square => backend.draw_rect(
                (x - h, y - h),
                (x + h, y + h),
                &if self.filled {
                    colour.filled()
                } else {
                    outline
                },
                self.filled,
            ),
            Shape::TriangleUp => polygon(backend, &[(0, -s - 1), (s, h), (-s, h)]),
            Shape::TriangleDown => polygon(backend, &[(0, s + 1), (s, -h), (-s, -h)]),
            Shape::Diamond => polygon(backend, &[(0, -s - 1), (s, 0), (0, s + 1), (-s, 0)]),
            Shape::Cross => {
                backend.draw_path(at(&[(-h, -h), (h, h)]), &line)?;
                backend.draw_path(at(&[(-h, h), (h, -h)]), &line)
            }
            Shape::Plus => {
                backend.draw_path(at(&[(-s, 0), (s, 0)]), &line)?;
                backend.draw_path(at(&[(0, -s), (0, s)]), &line)
            }
        }
    }
}

/// Registers the embedded font once (plotters' text needs one).
pub fn register_font() -> Result<(), String> {
    plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| "the embedded DejaVu font could not be loaded".to_owned())
}

/// One marker of the speed/error plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// Method name.
    pub method: String,
    /// Short parameter tag ("" for defaults).
    pub tag: String,
    /// Particles per second over all scenes of the dimension (all threads).
    pub rate: f64,
    /// 1 − M of the pooled confusion, floored at [`ERROR_FLOOR`].
    pub error: f64,
}

fn short_tag(row: &Row) -> String {
    if row.is_default {
        return String::new();
    }
    row.params
        .split(", ")
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| format!("{}{v}", k.chars().next().unwrap_or('?')))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Which time of a row a speed marker takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Timing {
    /// `seconds_all`: the run on all threads.
    AllThreads,
    /// `seconds_1`: the run on one thread (rows without it are left out).
    OneThread,
}

/// Pools the rows of one dimension by (method, parameters), their times on all threads.
pub fn markers(rows: &[Row], dim: usize) -> Vec<Marker> {
    markers_timed(rows, dim, Timing::AllThreads)
}

/// Pools the rows of one dimension by (method, parameters), with the time `timing` names.
pub fn markers_timed(rows: &[Row], dim: usize, timing: Timing) -> Vec<Marker> {
    let mut keys: Vec<(String, String, bool)> = Vec::new();
    for row in rows
        .iter()
        .filter(|r| r.dim == dim && r.confusion.is_some())
    {
        let key = (row.method.clone(), row.params.clone(), row.is_default);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.into_iter()
        .map(|(method, params, is_default)| {
            let mut pooled = Confusion::default();
            let (mut n, mut seconds) = (0usize, 0.0);
            let mut tag = String::new();
            for row in rows.iter().filter(|r| {
                r.dim == dim
                    && r.method == method
                    && r.params == params
                    && r.is_default == is_default
            }) {
                let time = match timing {
                    Timing::AllThreads => Some(row.seconds_all),
                    Timing::OneThread => row.seconds_1,
                };
                if let (Some(c), Some(time)) = (row.confusion, time) {
                    pooled.tp += c.tp;
                    pooled.tn += c.tn;
                    pooled.fp += c.fp;
                    pooled.fn_ += c.fn_;
                    n += row.n;
                    seconds += time;
                    tag = short_tag(row);
                }
            }
            Marker {
                method,
                tag,
                rate: if seconds > 0.0 {
                    n as f64 / seconds
                } else {
                    0.0
                },
                error: (1.0 - pooled.m()).max(ERROR_FLOOR),
            }
        })
        .filter(|m| m.rate > 0.0)
        .collect()
}

/// The speed/error markers of one dimension when the scale tier ran: default parameters only,
/// the error pooled over the fixture scenes as in [`markers`], the speed in particles/s pooled
/// over the scale scenes of that dimension on which every plotted method has a time (each
/// method's own scale scenes if there is none in common). Methods without a scale timing in
/// that dimension are left out.
pub fn scale_markers(rows: &[Row], scale: &ScaleOutcome, dim: usize) -> Vec<Marker> {
    let timed = |method: &str, scene: &str| {
        scale
            .rows
            .iter()
            .find(|r| r.scene == scene && r.method == method)
            .and_then(|r| r.median().map(|t| (r.n, t)))
    };
    let mut ms: Vec<Marker> = markers(rows, dim)
        .into_iter()
        .filter(|m| m.tag.is_empty())
        .filter(|m| {
            scale
                .rows
                .iter()
                .any(|r| r.dim == dim && r.method == m.method && r.median().is_some())
        })
        .collect();
    let scenes: Vec<&str> = scale
        .scenes
        .iter()
        .map(|(s, _, _)| s.as_str())
        .filter(|s| scale.rows.iter().any(|r| r.scene == *s && r.dim == dim))
        .collect();
    let common: Vec<&str> = scenes
        .iter()
        .copied()
        .filter(|s| ms.iter().all(|m| timed(&m.method, s).is_some()))
        .collect();
    for m in &mut ms {
        let own: Vec<&str> = if common.is_empty() {
            scenes.clone()
        } else {
            common.clone()
        };
        let (n, t) = own
            .iter()
            .filter_map(|s| timed(&m.method, s))
            .fold((0usize, 0.0), |(n, t), (a, b)| (n + a, t + b));
        m.rate = if t > 0.0 { n as f64 / t } else { 0.0 };
    }
    ms.retain(|m| m.rate > 0.0);
    ms
}

/// Seconds against |P| on log-log axes, one line per method over the lattice series of `dim`
/// with the method's markers; the Enright scene (3D) as a large outline of its marker.
fn scale_plot<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    scale: &ScaleOutcome,
    methods: &[String],
    dim: usize,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(err)?;
    let pts: Vec<(&str, bool, usize, f64)> = scale
        .rows
        .iter()
        .filter(|r| r.dim == dim)
        .filter_map(|r| {
            r.median().filter(|&t| t > 0.0).map(|t| {
                (
                    r.method.as_str(),
                    !(r.scene.starts_with("scale_ball") || r.scene.starts_with("scale_disc")),
                    r.n,
                    t,
                )
            })
        })
        .collect();
    if pts.is_empty() {
        return Ok(());
    }
    let nmin = pts.iter().map(|p| p.2).min().unwrap_or(1) as f64 / 1.5;
    let nmax = pts.iter().map(|p| p.2).max().unwrap_or(1) as f64 * 1.5;
    let tmin = pts.iter().map(|p| p.3).fold(f64::INFINITY, f64::min) / 2.0;
    let tmax = pts.iter().map(|p| p.3).fold(0.0, f64::max) * 2.0;
    let threads = scale.rows.first().map_or(0, |r| r.threads);
    let mut chart = log_log_chart(
        &root,
        format!(
            "{dim}D scale tier: seconds against |P| (median of {}, {threads} threads)",
            scale.runs
        ),
        (nmin..nmax, tmin..tmax),
        ("particles", "seconds"),
    )?;
    for method in methods {
        let style = style_of(method);
        let colour = style.colour;
        let mut line: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| p.0 == method && !p.1)
            .map(|p| (p.2 as f64, p.3))
            .collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        if line.is_empty() {
            continue;
        }
        chart
            .draw_series(LineSeries::new(line.clone(), colour.stroke_width(2)))
            .map_err(err)?
            .label(method.as_str())
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], colour.stroke_width(2))
                    + marker((10, 0), style, 5, true)
            });
        chart
            .draw_series(line.iter().map(|&p| marker(p, style, 5, true)))
            .map_err(err)?;
        chart
            .draw_series(
                pts.iter()
                    .filter(|p| p.0 == method && p.1)
                    .map(|p| marker((p.2 as f64, p.3), style, 8, false)),
            )
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)
}

fn method_names(rows: &[Row]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for row in rows {
        if !names.contains(&row.method) {
            names.push(row.method.clone());
        }
    }
    names
}

fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Width in pixels of the legend column beside the speed/error chart.
const LEGEND_WIDTH: u32 = 170;

/// The speed/error chart: particles per second against 1 − M on log scales, one marker per
/// method and parameter value in the method's [`MethodStyle`]. The default parameters are
/// large filled markers labelled with the method's name; other parameter values are small
/// outlines, unlabelled. A legend column on the right names every method's marker.
fn speed_vs_error<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    markers: &[Marker],
    methods: &[String],
    caption: String,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(err)?;
    let width = root.dim_in_pixel().0;
    let (area, legend) = root.split_horizontally(width.saturating_sub(LEGEND_WIDTH));
    let xmin = markers.iter().map(|m| m.rate).fold(f64::INFINITY, f64::min) / 2.0;
    let xmax = markers.iter().map(|m| m.rate).fold(0.0, f64::max) * 2.0;
    let ymax = markers.iter().map(|m| m.error).fold(ERROR_FLOOR, f64::max) * 2.0;
    let mut chart = log_log_chart(
        &area,
        caption,
        (xmin..xmax, ERROR_FLOOR / 2.0..ymax),
        ("particles per second", "1 - M"),
    )?;
    let shown: Vec<&String> = methods
        .iter()
        .filter(|method| markers.iter().any(|m| &m.method == *method))
        .collect();
    // Parameter variants first, so that the defaults stay on top.
    for default in [false, true] {
        for method in &shown {
            let style = style_of(method);
            let size = if default { 7 } else { 4 };
            chart
                .draw_series(
                    markers
                        .iter()
                        .filter(|m| &m.method == *method && m.tag.is_empty() == default)
                        .map(|m| marker((m.rate, m.error), style, size, default)),
                )
                .map_err(err)?;
        }
    }
    let font = ("sans-serif", 15).into_font();
    let text = TextStyle::from(font.clone()).color(&BLACK);
    let defaults: Vec<&Marker> = markers.iter().filter(|m| m.tag.is_empty()).collect();
    let mut labels = Vec::with_capacity(defaults.len());
    for m in &defaults {
        let (w, h) = area.estimate_text_size(&m.method, &text).map_err(err)?;
        labels.push((
            chart.backend_coord(&(m.rate, m.error)),
            (w as i32, h as i32),
        ));
    }
    let obstacles: Vec<(i32, i32)> = markers
        .iter()
        .map(|m| chart.backend_coord(&(m.rate, m.error)))
        .collect();
    let placed = place_labels(&labels, &obstacles, chart.plotting_area().get_pixel_range());
    for (m, (offset, leader)) in defaults.iter().zip(placed) {
        let colour = style_of(&m.method).colour;
        let at = (m.rate, m.error);
        if let Some(end) = leader {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(at) + PathElement::new(vec![(0, 0), end], colour.mix(0.6)),
                ))
                .map_err(err)?;
        }
        chart
            .draw_series(std::iter::once(
                EmptyElement::at(at) + Text::new(m.method.clone(), offset, text.clone()),
            ))
            .map_err(err)?;
    }
    speed_legend(&legend, &shown, markers.iter().any(|m| !m.tag.is_empty()))?;
    root.present().map_err(err)
}

/// The legend column of the speed/error chart: each method's marker and name, then what an
/// outline marker means when the chart has any.
fn speed_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    methods: &[&String],
    variants: bool,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let font = ("sans-serif", 15).into_font();
    let small = ("sans-serif", 13).into_font();
    let row = 24;
    let mut y = 60;
    for method in methods {
        area.draw(&marker((14, y), style_of(method), 7, true))
            .map_err(err)?;
        area.draw(&Text::new(method.to_string(), (30, y - 8), font.clone()))
            .map_err(err)?;
        y += row;
    }
    if variants {
        y += row / 2;
        let outline = MethodStyle {
            colour: RGBColor(90, 90, 90),
            shape: Shape::Circle,
        };
        area.draw(&marker((14, y), outline, 4, false))
            .map_err(err)?;
        for (k, line) in ["other parameter", "values (unlabelled)"]
            .iter()
            .enumerate()
        {
            area.draw(&Text::new(
                line.to_string(),
                (30, y - 7 + 16 * k as i32),
                small.clone(),
            ))
            .map_err(err)?;
        }
    }
    Ok(())
}

/// A label to place: its marker's pixel and the label's width and height.
type LabelBox = (BackendCoord, (i32, i32));

/// A placed label: the offset of its top-left corner from its marker, and the end of a leader
/// line from the marker (relative to it) when the label sits farther off.
type Placement = (BackendCoord, Option<BackendCoord>);

/// Places the label of each marker: `labels` holds each marker's pixel position and its
/// label's size, `obstacles` every marker drawn (pixel positions), `bounds` the plotting
/// area. Returns per label the offset of its top-left corner from its marker and, for a label
/// set farther off, the end of a leader line from the marker. Greedy, in the order given:
/// the first of a fixed list of places around the marker that overlaps no label placed
/// before, no marker and no border; else the place with the fewest overlaps.
fn place_labels(
    labels: &[LabelBox],
    obstacles: &[BackendCoord],
    bounds: (std::ops::Range<i32>, std::ops::Range<i32>),
) -> Vec<Placement> {
    type Rect = (i32, i32, i32, i32);
    let overlaps = |a: Rect, b: Rect| a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3;
    let mut taken: Vec<Rect> = Vec::new();
    let mut out = Vec::with_capacity(labels.len());
    for &((x, y), (w, h)) in labels {
        let gap = 10;
        let mut candidates: Vec<((i32, i32), bool)> = Vec::new();
        for (ring, far) in [(gap, false), (gap + 22, true)] {
            candidates.extend(
                [
                    (ring, -h / 2),
                    (-ring - w, -h / 2),
                    (-w / 2, -ring - h),
                    (-w / 2, ring),
                    (ring - 3, -ring - h + 3),
                    (ring - 3, ring - 3),
                    (-ring - w + 3, -ring - h + 3),
                    (-ring - w + 3, ring - 3),
                ]
                .map(|offset| (offset, far)),
            );
        }
        let cost = |(dx, dy): (i32, i32)| {
            let rect = (x + dx, y + dy, x + dx + w, y + dy + h);
            let outside = rect.0 < bounds.0.start
                || rect.2 > bounds.0.end
                || rect.1 < bounds.1.start
                || rect.3 > bounds.1.end;
            let labels_hit = taken.iter().filter(|&&t| overlaps(rect, t)).count();
            let markers_hit = obstacles
                .iter()
                .filter(|&&(px, py)| overlaps(rect, (px - 6, py - 6, px + 6, py + 6)))
                .count();
            100 * usize::from(outside) + 10 * labels_hit + markers_hit
        };
        let best = (0..candidates.len())
            .min_by_key(|&k| (cost(candidates[k].0), k))
            .map_or(((gap, -h / 2), false), |k| candidates[k]);
        let ((dx, dy), far) = best;
        taken.push((x + dx, y + dy, x + dx + w, y + dy + h));
        // The leader ends at the point of the label's box nearest to the marker.
        let leader = far.then(|| (0.clamp(dx, dx + w), 0.clamp(dy, dy + h)));
        out.push(((dx, dy), leader));
    }
    out
}

/// A chart whose axes are both logarithmic.
type LogLogChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// A captioned chart with logarithmic axes over `ranges`, its mesh and axis labels drawn.
fn log_log_chart<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    caption: String,
    (x, y): (std::ops::Range<f64>, std::ops::Range<f64>),
    (x_desc, y_desc): (&str, &str),
) -> Result<LogLogChart<'a, DB>, String>
where
    DB::ErrorType: 'static,
{
    let mut chart = ChartBuilder::on(root)
        .caption(caption, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x.log_scale(), y.log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// (method, [(depth, FP summed over scenes, seconds summed over scenes)]).
type DepthSeries = Vec<(String, Vec<(u32, u64, f64)>)>;

fn depth_series(rows: &[Row], dim: usize) -> DepthSeries {
    let mut series = Vec::new();
    for method in ["ia", "ge"] {
        let mut pts = Vec::new();
        for depth in 1..=12u32 {
            let tag = format!("depth={depth}");
            let sel: Vec<&Row> = rows
                .iter()
                .filter(|r| r.dim == dim && r.method == method && !r.is_default && r.params == tag)
                .collect();
            if sel.is_empty() {
                continue;
            }
            let fp = sel.iter().filter_map(|r| r.confusion).map(|c| c.fp).sum();
            let s = sel.iter().map(|r| r.seconds_all).sum();
            pts.push((depth, fp, s));
        }
        if !pts.is_empty() {
            series.push((method.to_owned(), pts));
        }
    }
    series
}

struct Panel<'a> {
    title: String,
    y_desc: &'a str,
    y_range: std::ops::Range<f64>,
    value: fn(&(u32, u64, f64)) -> f64,
}

fn depth_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: Panel<'_>,
    series: &DepthSeries,
    max_depth: u32,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let floor = panel.y_range.start;
    let mut chart = ChartBuilder::on(area)
        .caption(panel.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(1f64..max_depth.max(2) as f64, panel.y_range.log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("depth")
        .y_desc(panel.y_desc)
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()
        .map_err(err)?;
    for (method, pts) in series {
        let style = style_of(method);
        let colour = style.colour;
        let value = panel.value;
        let line: Vec<(f64, f64)> = pts
            .iter()
            .map(|p| (p.0 as f64, value(p).max(floor)))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), colour.stroke_width(2)))
            .map_err(err)?
            .label(method.as_str())
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], colour.stroke_width(2))
                    + marker((10, 0), style, 5, true)
            });
        chart
            .draw_series(line.into_iter().map(|p| marker(p, style, 5, true)))
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        .draw()
        .map_err(err)
}

fn depth_plot<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    rows: &[Row],
    dim: usize,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(err)?;
    let series = depth_series(rows, dim);
    let all = || series.iter().flat_map(|s| s.1.iter());
    let max_depth = all().map(|p| p.0).max().unwrap_or(8);
    let fp_max = all().map(|p| p.1).max().unwrap_or(1).max(1) as f64;
    let t_max = all().map(|p| p.2).fold(1e-6, f64::max);
    let panels = root.split_evenly((1, 2));
    depth_panel(
        &panels[0],
        Panel {
            title: format!("{dim}D: false positives against depth"),
            y_desc: "false positives (all scenes; 0 drawn at 0.5)",
            y_range: 0.5..fp_max * 2.0,
            value: |p| p.1 as f64,
        },
        &series,
        max_depth,
    )?;
    depth_panel(
        &panels[1],
        Panel {
            title: format!("{dim}D: time (all threads) against depth"),
            y_desc: "seconds (all scenes)",
            y_range: t_max / 1e4..t_max * 2.0,
            value: |p| p.2,
        },
        &series,
        max_depth,
    )?;
    root.present().map_err(err)
}

fn labels_plot<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    pic: &Picture,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(err)?;
    let count = pic.methods.len().max(1);
    let cols = count.min(3);
    let rows = count.div_ceil(cols);
    let panels = root.split_evenly((rows, cols));
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &pic.points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let pad = 0.03 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-12);
    for (panel, (method, labels)) in panels.iter().zip(&pic.methods) {
        let c = Confusion::from_labels(labels.as_slice(), pic.truth.as_slice()).map_err(err)?;
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!("{method}: FP {} (red), FN {} (blue)", c.fp, c.fn_),
                ("sans-serif", 16),
            )
            .margin(8)
            .build_cartesian_2d(lo[0] - pad..hi[0] + pad, lo[1] - pad..hi[1] + pad)
            .map_err(err)?;
        let mut layers: [Vec<(f64, f64)>; 4] = Default::default();
        for (k, p) in pic.points.iter().enumerate() {
            let layer = match (labels.is_boundary(k), pic.truth.is_boundary(k)) {
                (false, false) => 0,
                (true, true) => 1,
                (true, false) => 2,
                (false, true) => 3,
            };
            layers[layer].push((p[0], p[1]));
        }
        let styles = [
            (RGBColor(205, 205, 205), 1),
            (RGBColor(40, 150, 60), 2),
            (RGBColor(220, 30, 30), 3),
            (RGBColor(30, 60, 230), 3),
        ];
        for (layer, (colour, size)) in layers.iter().zip(styles) {
            chart
                .draw_series(layer.iter().map(|&p| Circle::new(p, size, colour.filled())))
                .map_err(err)?;
        }
    }
    root.present().map_err(err)
}

/// The feature classes of a 2D scene (thesis Fig. 15 colours: regular boundary blue, droplet
/// cyan, ligament yellow, sheet magenta; interior grey).
fn features_plot<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    pic: &Picture,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(err)?;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &pic.points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let pad = 0.03 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-12);
    let count = |code: i8| pic.features.iter().filter(|&&f| f == code).count();
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "{}: {} droplet (cyan), {} ligament (yellow), {} regular (blue)",
                pic.scene,
                count(0),
                count(1),
                count(3)
            ),
            ("sans-serif", 16),
        )
        .margin(8)
        .build_cartesian_2d(lo[0] - pad..hi[0] + pad, lo[1] - pad..hi[1] + pad)
        .map_err(err)?;
    // Drawn interior first so that the features stay on top.
    let styles: [(i8, RGBColor, i32); 5] = [
        (-1, RGBColor(200, 200, 200), 1),
        (3, RGBColor(30, 60, 230), 2),
        (2, RGBColor(220, 0, 220), 3),
        (1, RGBColor(230, 190, 0), 3),
        (0, RGBColor(0, 200, 220), 3),
    ];
    for (code, colour, size) in styles {
        let layer = pic
            .points
            .iter()
            .zip(&pic.features)
            .filter(|(_, &f)| f == code)
            .map(|(p, _)| Circle::new((p[0], p[1]), size, colour.filled()));
        chart.draw_series(layer).map_err(err)?;
    }
    root.present().map_err(err)
}

/// The scene drawn for the README ([`write_frame`]): a frame of the single-vortex flow
/// (Bell–Colella–Glaz, the JCP paper's Fig. 9 experiment), where a blob is stretched into a
/// spiral with a thin tail, so that surface, ligament and droplets are all in one picture.
pub const FRAME_SCENE: &str = "vortex2d_t4";

/// One 2D frame with its `exact` boundary particles: interior particles small and grey, boundary
/// particles larger and dark blue, on a square window with no axes. Written as PNG to `path`
/// (640 × 640 pixels, a few tens of kilobytes).
pub fn write_frame(pic: &Picture, path: &Path) -> Result<(), String> {
    let root = BitMapBackend::new(path, (640, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let window = square_window(pic.points.iter().map(|p| (p[0], p[1])));
    let boundary = pic.truth.boundary_count();
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "{}: {boundary} of {} particles on the boundary (exact)",
                pic.scene,
                pic.points.len()
            ),
            ("sans-serif", 18),
        )
        .margin(10)
        .build_cartesian_2d(window.0 .0..window.0 .1, window.1 .0..window.1 .1)
        .map_err(err)?;
    // Interior first, so that the boundary stays on top.
    for (on_boundary, colour, size) in [
        (false, RGBColor(190, 190, 190), 1),
        (true, RGBColor(25, 55, 170), 2),
    ] {
        let layer = pic
            .points
            .iter()
            .enumerate()
            .filter(|(k, _)| pic.truth.is_boundary(*k) == on_boundary)
            .map(|(_, p)| Circle::new((p[0], p[1]), size, colour.filled()));
        chart.draw_series(layer).map_err(err)?;
    }
    root.present().map_err(err)
}

/// Colours and sizes of the four label layers: interior, boundary, false positive, false
/// negative.
const LAYER_STYLES: [(RGBColor, i32); 4] = [
    (RGBColor(205, 205, 205), 1),
    (RGBColor(40, 150, 60), 2),
    (RGBColor(220, 30, 30), 3),
    (RGBColor(30, 60, 230), 3),
];

/// Layer of a particle: 0 interior, 1 boundary (both agree), 2 false positive, 3 false negative.
fn layer_of(said: bool, truth: bool) -> usize {
    match (said, truth) {
        (false, false) => 0,
        (true, true) => 1,
        (true, false) => 2,
        (false, true) => 3,
    }
}

/// A square window (lo, hi) around the points, so that shapes are not distorted.
fn square_window(points: impl Iterator<Item = (f64, f64)>) -> ((f64, f64), (f64, f64)) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (x, y) in points {
        lo = [lo[0].min(x), lo[1].min(y)];
        hi = [hi[0].max(x), hi[1].max(y)];
    }
    if !(lo[0] <= hi[0] && lo[1] <= hi[1]) {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    let half = 0.53 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-12);
    let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    ((c[0] - half, c[0] + half), (c[1] - half, c[1] + half))
}

fn scatter_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: String,
    window: ((f64, f64), (f64, f64)),
    layers: &[Vec<(f64, f64)>; 4],
    sizes: [i32; 4],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let ((x0, x1), (y0, y1)) = window;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 15))
        .margin(8)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    for ((layer, (colour, _)), size) in layers.iter().zip(LAYER_STYLES).zip(sizes) {
        chart
            .draw_series(layer.iter().map(|&p| Circle::new(p, size, colour.filled())))
            .map_err(err)?;
    }
    Ok(())
}

/// The picture of one method's worst scene (see the module docs).
fn failure_plot<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    pic: &FailurePicture,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(err)?;
    let c = Confusion::from_labels(pic.labels.as_slice(), pic.truth.as_slice()).map_err(err)?;
    let head = format!(
        "{} on {} (M {:.4}): FN {} (blue), FP {} (red)",
        pic.method, pic.scene, pic.m, c.fn_, c.fp
    );
    let root = root.titled(&head, ("sans-serif", 17)).map_err(err)?;
    let n = pic.truth.len();
    let layer = |i: usize| layer_of(pic.labels.is_boundary(i), pic.truth.is_boundary(i));
    let sizes = LAYER_STYLES.map(|s| s.1);
    match pic.slab() {
        None => {
            let xy = |i: usize| (pic.point(i)[0], pic.point(i)[1]);
            let mut layers: [Vec<(f64, f64)>; 4] = Default::default();
            for i in 0..n {
                layers[layer(i)].push(xy(i));
            }
            let window = square_window((0..n).map(xy));
            scatter_panel(&root, String::new(), window, &layers, sizes)?;
        }
        Some((axis, lo, hi)) => {
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            let names = ["x", "y", "z"];
            let xy = |i: usize| (pic.point(i)[a], pic.point(i)[b]);
            let window = square_window((0..n).map(xy));
            let panels = root.split_evenly((1, 2));
            let mut slab: [Vec<(f64, f64)>; 4] = Default::default();
            let mut all: [Vec<(f64, f64)>; 4] = Default::default();
            let mut in_slab = 0;
            for i in 0..n {
                let t = pic.point(i)[axis];
                let k = layer(i);
                if (lo..=hi).contains(&t) {
                    slab[k].push(xy(i));
                    in_slab += usize::from(k >= 2);
                }
                // The projection: everything grey, the misses on top.
                all[if k >= 2 { k } else { 0 }].push(xy(i));
            }
            scatter_panel(
                &panels[0],
                format!(
                    "slab {lo:.4} <= {} <= {hi:.4} (2r): {in_slab} misses",
                    names[axis]
                ),
                window,
                &slab,
                sizes,
            )?;
            scatter_panel(
                &panels[1],
                format!(
                    "all particles projected along {} ({}, {} axes)",
                    names[axis], names[a], names[b]
                ),
                window,
                &all,
                [1, 1, 2, 2],
            )?;
        }
    }
    root.present().map_err(err)
}

/// File name of the domain picture of `scene` (`domain_<scene>.<ext>`).
pub fn domain_file(scene: &str, ext: &str) -> String {
    format!("domain_{}.{ext}", file_stem(scene))
}

/// The exact labels of a scene with a domain (see the module docs).
fn domain_plot<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    pic: &DomainPicture,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(err)?;
    let names = ["x", "y", "z"];
    let boundary = pic.boundary.iter().filter(|&&b| b).count();
    let interface = pic.interface.iter().filter(|&&b| b).count();
    let mut head = format!("{}: exact, {} free surface (green)", pic.scene, boundary);
    if !pic.interface.is_empty() {
        head.push_str(&format!(", {interface} interface (orange)"));
    }
    if pic.dim == 3 {
        head.push_str(" in the slab across y");
    }
    let root = root.titled(&head, ("sans-serif", 17)).map_err(err)?;
    // The window holds the particles, the walls and every solid bound.
    let centre = pic.points.first().copied().unwrap_or([0.0, 0.0]);
    let bounds: Vec<(f64, f64)> = pic
        .solids
        .iter()
        .map(|&(k, value, _)| {
            if k == 0 {
                (value, centre[1])
            } else {
                (centre[0], value)
            }
        })
        .collect();
    let points = pic.points.iter().chain(&pic.walls).map(|p| (p[0], p[1]));
    let ((x0, x1), (y0, y1)) = square_window(points.chain(bounds));
    let mut chart = ChartBuilder::on(&root)
        .caption(&pic.about, ("sans-serif", 14))
        .margin(10)
        .x_label_area_size(28)
        .y_label_area_size(40)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(names[pic.axes[0]])
        .y_desc(names[pic.axes[1]])
        .draw()
        .map_err(err)?;
    let wall = RGBColor(150, 150, 150);
    chart
        .draw_series(
            pic.walls
                .iter()
                .map(|p| Circle::new((p[0], p[1]), 2, wall.filled())),
        )
        .map_err(err)?;
    // Interior by phase (phase 0 pale blue, others pale sand), then the labels on top.
    let interior = |i: usize| {
        if pic.phases.get(i).copied().unwrap_or(0) == 0 {
            RGBColor(170, 195, 230)
        } else {
            RGBColor(230, 205, 160)
        }
    };
    let is_interface = |i: usize| pic.interface.get(i).copied().unwrap_or(false);
    let n = pic.points.len();
    let xy = |i: usize| (pic.points[i][0], pic.points[i][1]);
    chart
        .draw_series(
            (0..n)
                .filter(|&i| !pic.boundary[i] && !is_interface(i))
                .map(|i| Circle::new(xy(i), 2, interior(i).filled())),
        )
        .map_err(err)?;
    chart
        .draw_series(
            (0..n)
                .filter(|&i| is_interface(i))
                .map(|i| Circle::new(xy(i), 3, RGBColor(240, 130, 0).filled())),
        )
        .map_err(err)?;
    chart
        .draw_series(
            (0..n)
                .filter(|&i| pic.boundary[i])
                .map(|i| Circle::new(xy(i), 3, RGBColor(40, 150, 60).filled())),
        )
        .map_err(err)?;
    // Solid bounds: a line, with short ticks into the solid side.
    let solid = RGBColor(60, 60, 60);
    let tick = 0.015 * (x1 - x0);
    for &(k, value, below) in &pic.solids {
        let sign = if below { -1.0 } else { 1.0 };
        type Segment = [(f64, f64); 2];
        let (line, ticks): (Segment, Vec<Segment>) = if k == 0 {
            let ticks = (0..=20)
                .map(|j| y0 + (y1 - y0) * f64::from(j) / 20.0)
                .map(|y| [(value, y), (value + sign * tick, y - tick)])
                .collect();
            ([(value, y0), (value, y1)], ticks)
        } else {
            let ticks = (0..=20)
                .map(|j| x0 + (x1 - x0) * f64::from(j) / 20.0)
                .map(|x| [(x, value), (x - tick, value + sign * tick)])
                .collect();
            ([(x0, value), (x1, value)], ticks)
        };
        chart
            .draw_series(LineSeries::new(line, solid.stroke_width(2)))
            .map_err(err)?;
        chart
            .draw_series(
                ticks
                    .into_iter()
                    .map(|t| PathElement::new(t.to_vec(), solid)),
            )
            .map_err(err)?;
    }
    // Periodic bounds: dashed lines at both ends of the period.
    for &(k, lo, hi) in &pic.periodic {
        for value in [lo, hi] {
            let dashes = (0..40).filter(|j| j % 2 == 0).map(|j| {
                let (a, b) = (f64::from(j) / 40.0, f64::from(j + 1) / 40.0);
                if k == 0 {
                    vec![(value, y0 + a * (y1 - y0)), (value, y0 + b * (y1 - y0))]
                } else {
                    vec![(x0 + a * (x1 - x0), value), (x0 + b * (x1 - x0), value)]
                }
            });
            chart
                .draw_series(dashes.map(|d| PathElement::new(d, RGBColor(120, 60, 160))))
                .map_err(err)?;
        }
    }
    root.present().map_err(err)
}

/// Writes the domain pictures (SVG and PNG) into `dir`; returns the files written.
pub fn write_domains(pictures: &[DomainPicture], dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    for pic in pictures {
        let svg = dir.join(domain_file(&pic.scene, "svg"));
        domain_plot(SVGBackend::new(&svg, (760, 800)).into_drawing_area(), pic)?;
        let png = dir.join(domain_file(&pic.scene, "png"));
        domain_plot(
            BitMapBackend::new(&png, (760, 800)).into_drawing_area(),
            pic,
        )?;
        written.extend([svg, png]);
    }
    Ok(written)
}

/// File name of the failure picture of `method` (`fail_<method>.<ext>`).
pub fn failure_file(method: &str, ext: &str) -> String {
    format!("fail_{}.{ext}", file_stem(method))
}

/// Writes the failure pictures (SVG and PNG) into `dir`; returns the files written.
pub fn write_failures(pictures: &[FailurePicture], dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    for pic in pictures {
        let size = if pic.dim == 3 {
            (1400, 720)
        } else {
            (720, 720)
        };
        let svg = dir.join(failure_file(&pic.method, "svg"));
        failure_plot(SVGBackend::new(&svg, size).into_drawing_area(), pic)?;
        let png = dir.join(failure_file(&pic.method, "png"));
        failure_plot(BitMapBackend::new(&png, size).into_drawing_area(), pic)?;
        written.extend([svg, png]);
    }
    Ok(written)
}

fn file_stem(scene: &str) -> String {
    scene
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Size of the speed/error charts, in pixels (the legend column included).
const SPEED_SIZE: (u32, u32) = (1000, 680);

/// Whether every run of `rows` that was scored has a one-thread time.
fn has_one_thread(rows: &[Row]) -> bool {
    rows.iter()
        .filter(|r| r.confusion.is_some())
        .all(|r| r.seconds_1.is_some())
}

/// The speed/error pictures of `BENCHMARKS.md` (`speed_vs_error_{2d,3d}.png`, PNG only) into
/// `dir`: the report's chart over the fixture scenes, timed on one thread when every scored
/// run has a one-thread time (as the page's tables are), else on all threads. Returns the
/// dimension and file of each picture written.
pub fn write_benchmark_pictures(rows: &[Row], dir: &Path) -> Result<Vec<(usize, PathBuf)>, String> {
    let methods = method_names(rows);
    let timing = if has_one_thread(rows) {
        Timing::OneThread
    } else {
        Timing::AllThreads
    };
    let mut written = Vec::new();
    for dim in [2, 3] {
        let ms = markers_timed(rows, dim, timing);
        if ms.is_empty() {
            continue;
        }
        let mut scenes: Vec<&str> = rows
            .iter()
            .filter(|r| r.dim == dim && r.confusion.is_some())
            .map(|r| r.scene.as_str())
            .collect();
        scenes.sort_unstable();
        scenes.dedup();
        let threads = match timing {
            Timing::OneThread => "one thread".to_owned(),
            Timing::AllThreads => format!(
                "{} threads",
                rows.iter().map(|r| r.threads).max().unwrap_or(0)
            ),
        };
        let caption = format!(
            "{dim}D: speed ({threads}) against error, pooled over {} scenes",
            scenes.len()
        );
        let png = dir.join(format!("speed_vs_error_{dim}d.png"));
        speed_vs_error(
            BitMapBackend::new(&png, SPEED_SIZE).into_drawing_area(),
            &ms,
            &methods,
            caption,
        )?;
        written.push((dim, png));
    }
    Ok(written)
}

/// Writes every plot as SVG and PNG into `dir`; returns the files written.
pub fn write_all(outcome: &Outcome, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let methods = method_names(&outcome.rows);
    let mut written = Vec::new();
    let mut methods = methods;
    if let Some(scale) = &outcome.scale {
        for row in &scale.rows {
            if !methods.contains(&row.method) {
                methods.push(row.method.clone());
            }
        }
    }
    for dim in [2, 3] {
        let scaled = outcome
            .scale
            .as_ref()
            .map(|s| scale_markers(&outcome.rows, s, dim))
            .filter(|ms| !ms.is_empty());
        let caption = if scaled.is_some() {
            format!(
                "{dim}D: speed (scale tier, all threads) against error (fixture scenes), \
                 default parameters"
            )
        } else {
            format!("{dim}D: speed against error (pooled over scenes, all threads)")
        };
        let ms = scaled.unwrap_or_else(|| markers(&outcome.rows, dim));
        if !ms.is_empty() {
            let stem = dir.join(format!("speed_vs_error_{dim}d"));
            let svg = stem.with_extension("svg");
            speed_vs_error(
                SVGBackend::new(&svg, SPEED_SIZE).into_drawing_area(),
                &ms,
                &methods,
                caption.clone(),
            )?;
            let png = stem.with_extension("png");
            speed_vs_error(
                BitMapBackend::new(&png, SPEED_SIZE).into_drawing_area(),
                &ms,
                &methods,
                caption,
            )?;
            written.extend([svg, png]);
        }
        if let Some(scale) = outcome
            .scale
            .as_ref()
            .filter(|s| s.rows.iter().any(|r| r.dim == dim && r.median().is_some()))
        {
            let stem = dir.join(format!("scale_{dim}d"));
            let svg = stem.with_extension("svg");
            scale_plot(
                SVGBackend::new(&svg, (1000, 700)).into_drawing_area(),
                scale,
                &methods,
                dim,
            )?;
            let png = stem.with_extension("png");
            scale_plot(
                BitMapBackend::new(&png, (1000, 700)).into_drawing_area(),
                scale,
                &methods,
                dim,
            )?;
            written.extend([svg, png]);
        }
        let has_depths = outcome
            .rows
            .iter()
            .any(|r| r.dim == dim && (r.method == "ia" || r.method == "ge") && !r.is_default);
        if has_depths {
            let stem = dir.join(format!("depth_{dim}d"));
            let svg = stem.with_extension("svg");
            depth_plot(
                SVGBackend::new(&svg, (1200, 500)).into_drawing_area(),
                &outcome.rows,
                dim,
            )?;
            let png = stem.with_extension("png");
            depth_plot(
                BitMapBackend::new(&png, (1200, 500)).into_drawing_area(),
                &outcome.rows,
                dim,
            )?;
            written.extend([svg, png]);
        }
    }
    for pic in outcome.pictures.iter().filter(|p| !p.methods.is_empty()) {
        let cols = pic.methods.len().min(3) as u32;
        let rows = (pic.methods.len() as u32).div_ceil(cols);
        let size = (420 * cols, 420 * rows);
        let stem = dir.join(format!("labels_{}", file_stem(&pic.scene)));
        let svg = stem.with_extension("svg");
        labels_plot(SVGBackend::new(&svg, size).into_drawing_area(), pic)?;
        let png = stem.with_extension("png");
        labels_plot(BitMapBackend::new(&png, size).into_drawing_area(), pic)?;
        written.extend([svg, png]);
    }
    for pic in outcome
        .pictures
        .iter()
        .filter(|p| p.features.len() == p.points.len() && !p.points.is_empty())
    {
        let stem = dir.join(format!("features_{}", file_stem(&pic.scene)));
        let svg = stem.with_extension("svg");
        features_plot(SVGBackend::new(&svg, (700, 700)).into_drawing_area(), pic)?;
        let png = stem.with_extension("png");
        features_plot(
            BitMapBackend::new(&png, (700, 700)).into_drawing_area(),
            pic,
        )?;
        written.extend([svg, png]);
    }
    written.extend(write_failures(&outcome.failure_pictures, dir)?);
    written.extend(write_domains(&outcome.domain_pictures, dir)?);
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scale::ScaleRow;

    fn row(scene: &str, method: &str, params: &str, fp: u64, seconds: f64) -> Row {
        Row {
            scene: scene.into(),
            dim: 3,
            n: 100,
            radius: 1.0,
            method: method.into(),
            params: params.into(),
            is_default: params.is_empty(),
            certified: true,
            misses: None,
            confusion: Some(Confusion {
                tp: 10,
                tn: 90 - fp,
                fp,
                fn_: 0,
            }),
            seconds_1: None,
            seconds_all: seconds,
            threads: 2,
            error: None,
            unsupported: false,
            interface: None,
            interface_confusion: None,
        }
    }

    fn scale_row(scene: &str, method: &str, n: usize, seconds: Option<f64>) -> ScaleRow {
        ScaleRow {
            scene: scene.into(),
            dim: 3,
            n,
            radius: 1.2,
            method: method.into(),
            seconds: seconds.into_iter().collect(),
            threads: 2,
            confusion: None,
            peak_bytes: None,
            skipped: None,
        }
    }

    /// With a scale tier, the speed of a marker comes from the scale scenes every method ran
    /// (not from the small fixture scenes), the error still from the fixture scenes, and
    /// parameter variants are left out.
    #[test]
    fn scale_markers_take_the_speed_from_the_common_scale_scenes() {
        let rows = vec![
            row("small", "exact", "", 0, 0.001),
            row("small", "ia", "", 9, 0.01),
            row("small", "ia", "depth=2", 30, 0.002),
        ];
        let scale = ScaleOutcome {
            rows: vec![
                scale_row("s_10k", "exact", 10_000, Some(0.1)),
                scale_row("s_10k", "ia", 10_000, Some(1.0)),
                scale_row("s_1M", "exact", 1_000_000, Some(4.0)),
                // ia stopped at the budget: the 1M set is not common, so not pooled.
                scale_row("s_1M", "ia", 1_000_000, None),
            ],
            scenes: vec![
                ("s_10k".into(), String::new(), 0.0),
                ("s_1M".into(), String::new(), 0.0),
            ],
            thread_scan: None,
            runs: 3,
            budget: 60.0,
        };
        let ms = scale_markers(&rows, &scale, 3);
        assert_eq!(ms.len(), 2, "{ms:?}");
        let exact = ms.iter().find(|m| m.method == "exact").unwrap();
        let ia = ms.iter().find(|m| m.method == "ia").unwrap();
        assert_eq!(exact.rate, 10_000.0 / 0.1);
        assert_eq!(ia.rate, 10_000.0 / 1.0);
        assert_eq!(exact.error, ERROR_FLOOR);
        // ia: FPR 9/90, M = 0.9.
        assert!((ia.error - 0.1).abs() < 1e-12);
        assert!(scale_markers(&rows, &scale, 2).is_empty());
    }

    /// Every registered method has its own entry in the style table, and no two share both
    /// colour and shape.
    #[test]
    fn every_method_has_its_own_colour_and_marker() {
        let methods = boundary::methods();
        for method in &methods {
            assert!(
                STYLES.iter().any(|(name, _, _)| name == method),
                "{method} has no style"
            );
        }
        for (k, (a, ca, sa)) in STYLES.iter().enumerate() {
            for (b, cb, sb) in &STYLES[k + 1..] {
                assert!(a != b && (ca != cb || sa != sb), "{a} and {b}");
            }
            // Colours are not reused across methods either.
            assert_eq!(STYLES.iter().filter(|(_, c, _)| c == ca).count(), 1, "{a}");
        }
        assert_eq!(style_of("exact"), style_of("exact"));
        assert_eq!(style_of("no-such-method").colour, RGBColor(70, 70, 70));
    }

    /// Labels of markers that sit on one another are placed apart, inside the plot.
    #[test]
    fn labels_of_coincident_markers_do_not_overlap() {
        let labels = [((200, 200), (40, 14)); 4];
        let obstacles = [(200, 200)];
        let placed = place_labels(&labels, &obstacles, (0..400, 0..400));
        let rects: Vec<(i32, i32, i32, i32)> = placed
            .iter()
            .map(|&((dx, dy), _)| (200 + dx, 200 + dy, 240 + dx, 214 + dy))
            .collect();
        for (k, a) in rects.iter().enumerate() {
            assert!(a.0 >= 0 && a.1 >= 0 && a.2 <= 400 && a.3 <= 400, "{a:?}");
            for b in &rects[k + 1..] {
                let overlap = a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3;
                assert!(!overlap, "{a:?} {b:?}");
            }
        }
    }

    /// The page's pictures: one per dimension with scored runs, timed on one thread when
    /// every run has a one-thread time.
    #[test]
    fn the_benchmark_pictures_are_written_per_dimension() {
        let mut rows = vec![
            row("a", "exact", "", 0, 0.001),
            row("a", "ia", "", 9, 0.01),
            row("a", "ia", "depth=2", 30, 0.002),
        ];
        for r in &mut rows {
            r.seconds_1 = Some(2.0 * r.seconds_all);
        }
        let ms = markers_timed(&rows, 3, Timing::OneThread);
        let exact = ms.iter().find(|m| m.method == "exact").unwrap();
        assert_eq!(exact.rate, 100.0 / 0.002);
        register_font().unwrap();
        let dir = tempfile::tempdir().unwrap();
        let written = write_benchmark_pictures(&rows, dir.path()).unwrap();
        assert_eq!(written.len(), 1, "{written:?}");
        assert_eq!(written[0].0, 3);
        assert!(written[0].1.ends_with("speed_vs_error_3d.png"));
        assert!(std::fs::metadata(&written[0].1).unwrap().len() > 1000);
    }

    #[test]
    fn the_scale_plot_is_written_for_each_dimension_with_times() {
        let outcome = Outcome {
            rows: vec![row("small", "exact", "", 0, 0.001)],
            scale: Some(ScaleOutcome {
                rows: vec![
                    scale_row("scale_ball3d_10k", "exact", 10_000, Some(0.1)),
                    scale_row("scale_ball3d_100k", "exact", 100_000, Some(1.1)),
                    scale_row("scale_enright3d_1.9M", "exact", 1_900_000, Some(20.0)),
                ],
                scenes: Vec::new(),
                thread_scan: None,
                runs: 3,
                budget: 60.0,
            }),
            ..Default::default()
        };
        register_font().unwrap();
        let dir = tempfile::tempdir().unwrap();
        let written = write_all(&outcome, dir.path()).unwrap();
        let names: Vec<String> = written
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert!(names.contains(&"scale_3d.svg".to_owned()), "{names:?}");
        assert!(names.contains(&"scale_3d.png".to_owned()));
        assert!(!names.iter().any(|n| n.starts_with("scale_2d")));
        let svg = std::fs::read_to_string(dir.path().join("scale_3d.svg")).unwrap();
        assert!(
            svg.contains("exact") && svg.contains("seconds against"),
            "{svg}"
        );
    }
}
