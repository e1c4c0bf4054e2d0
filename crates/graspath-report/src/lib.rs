//! Reports of a selection: JSON of every candidate with every score, the ranked pairs and a
//! summary; the paper's figures as SVG and PNG plots; a self-contained HTML page with a 3D view.
//! Everything is rendered in memory; [`graspath::output_files::write_files`] writes the set atomically
//! (no partial output on error).
#![warn(unreachable_pub)]

mod figures;
mod html;
mod json;
mod lines;
mod map;
mod parquet;
mod plots;
mod pretty;
mod scene;
mod stage;
mod style;
mod text;
mod trajectory;
mod witness;
mod world;

pub use figures::{figures, Figure};
pub use html::{render_report, report_html, Inline, INLINE_SVG_MAX_CELLS};
pub use json::{
    candidates_json, candidates_json_bytes, candidates_json_with, nothing_selected, pairs_json,
    summary_json, tied_pairs, write_candidate_line, write_candidates_json, write_ranking_jsonl,
};
pub use lines::{Axes, LegendEntry, Line, LinePlot, LineStyle, SecondaryLabels, MARK_STYLE};
pub use map::{placement_figures, placement_map_json};
pub use parquet::{write_ranking_parquet, CandidatesParquet, ParquetOutputError};
pub use plots::{
    render_png, render_svg, render_svg_and_png, viridis, Cell, Heatmap, Plot, PlotError,
    HEATMAP_SIZE, LINE_SIZE, MARKED_COLOUR, MISSING_COLOUR,
};
pub use scene::{scene_json, MAX_BODY_MOTIONS_PER_ARM, MAX_MOTIONS_PER_ARM, MAX_WITNESSES_PER_ARM};
pub use stage::{
    stage, Stage, Torso, VIEW_ASPECT, VIEW_AZIMUTH, VIEW_ELEVATION, VIEW_FILL, VIEW_FOV_DEG,
};
pub use text::{best_pair_sentence, best_sentence, findings_sentences, percent};
pub use trajectory::{trajectory_csvs, trajectory_files, trajectory_json};
pub use world::{MAX_VIEW_POINTS, MAX_VIEW_TRIANGLES};
