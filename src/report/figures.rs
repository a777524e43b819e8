//! The figures of a section, one kind per module behind one interface: each kind ([`Figures`])
//! says whether a run has its data and draws its figures; [`write_figures`] goes through the
//! kinds in the order of the page.
//!
//! A section gets only the figures it has data for: no mesh picture, no mesh figure. A load-step
//! run (the forming of §IV.2.4.7, Fig. IV.54) moves its body, so the convergence and cost plots
//! (one mesh hierarchy refined cycle after cycle), the mesh figure (axis-parallel cell boxes) and
//! the partition figure (faces on the undeformed strip) do not apply; it gets the per-step chart,
//! a frame per step and their animation instead.

use std::io;
use std::path::{Path, PathBuf};

use super::{
    convergence, deformed, estimate_name, field, file_stem, film, forming, meshes, model_plots,
    EstimateName, Section,
};
use crate::experiment::ThesisFigures;
use crate::results::RunResult;
use crate::thesis::ThesisTable;

/// A figure written for a section, as the page refers to it.
pub(crate) struct Figure {
    /// File name inside `figures/`.
    pub file: String,
    /// Alternative text and caption.
    pub caption: String,
    /// Further files of the figure inside `figures/`, listed as links under it with their
    /// labels (the frames of a load-step animation); usually none.
    pub links: Vec<(String, String)>,
}

/// What a kind of figure draws from: the section's run and printed table, the other runs of the
/// page, and where the files go.
pub(super) struct Drawing<'a> {
    pub fig_dir: &'a Path,
    pub run: &'a RunResult,
    pub thesis: &'a ThesisTable,
    /// Every run of the page, for the figures that set a run beside its related tables.
    pub runs: &'a [&'a RunResult],
    /// The file-name form of the table id ([`file_stem`]), the start of every file name.
    pub stem: String,
    /// The name of the run's estimate on axes and in captions.
    pub eta: EstimateName,
}

impl Drawing<'_> {
    /// The thesis figures that show the run, cited in the captions.
    pub fn cited(&self) -> &ThesisFigures {
        &self.thesis.figures
    }

    /// The figure `<stem>-<kind>.svg` with its caption, and the path to draw it at.
    pub fn figure(&self, kind: &str, caption: String) -> (Figure, PathBuf) {
        let file = format!("{}-{kind}.svg", self.stem);
        let path = self.fig_dir.join(&file);
        let figure = Figure {
            file,
            caption,
            links: Vec::new(),
        };
        (figure, path)
    }
}

/// One kind of figure of a section.
pub(super) trait Figures: Sync {
    /// Whether the run has the data of this kind.
    fn applies(&self, run: &RunResult) -> bool;
    /// Draw this kind's figures of the section (one, or one per picture) and say how the page
    /// shows them.
    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>>;
}

/// Every kind of figure, in the order of the page. The first four are the section's headline
/// and exclude each other: the model and model error per cycle of a model-adaptive run, the
/// per-step chart of a load-step run, the residuals of Uzawa's algorithm, or else the
/// convergence of the estimate.
const KINDS: [&dyn Figures; 13] = [
    &model_plots::ModelAdaptivity,
    &forming::Steps,
    &film::Uzawa,
    &convergence::Convergence,
    &model_plots::Partition,
    &convergence::Accuracy,
    &convergence::Cost,
    &meshes::Meshes,
    &forming::Animation,
    &deformed::Deformed,
    &field::Fields,
    &film::ModelCuts,
    &film::Related,
];

/// Draw every figure one section has data for, in the order of the page.
pub(super) fn write_figures(
    fig_dir: &Path,
    section: &Section,
    runs: &[&RunResult],
) -> io::Result<Vec<Figure>> {
    let at = Drawing {
        fig_dir,
        run: section.run,
        thesis: section.thesis,
        runs,
        stem: file_stem(&section.run.table),
        eta: estimate_name(section.run),
    };
    let mut figures = Vec::new();
    for kind in KINDS {
        if kind.applies(at.run) {
            figures.extend(kind.write(&at)?);
        }
    }
    Ok(figures)
}

/// `" (cf. thesis Fig. IV.12)"` for a figure the thesis draws (a number of the experiment's
/// `[figures]`), empty otherwise.
pub(super) fn cf(figure: &Option<String>) -> String {
    figure
        .as_ref()
        .map_or(String::new(), |f| format!(" (cf. thesis Fig. {f})"))
}

/// `kind` when a run has one picture of that kind, `kind-i` when it has several.
pub(super) fn indexed(kind: &str, i: usize, n: usize) -> String {
    if n > 1 {
        format!("{kind}-{i}")
    } else {
        kind.to_string()
    }
}
