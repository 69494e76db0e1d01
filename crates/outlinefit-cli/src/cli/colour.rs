//! The colour options of `trace` and `batch` (`--palette`, `--layout`) and what the
//! command line says about a colour trace.

use anyhow::bail;
use clap::Args;
use outlinefit::colour::{ColourOptions, ColourTrace, Layout, PaletteSize};
use outlinefit::{Config, Format, Method};

/// Colour tracing.
#[derive(Args, Debug, Clone)]
pub(crate) struct ColourArgs {
    /// Trace in colour: `auto` (the image's flat colours) or at most N colours.
    ///
    /// Trace in colour: every flat colour of the image becomes regions whose shared
    /// boundaries are fitted once, placed to a fraction of a pixel from the anti-aliased
    /// pixels between the colours; transparency stays transparent. `auto` keeps the
    /// colours found (at most 64), N merges the rarest into their nearest until N are left.
    /// Writes SVG (one group per colour), PDF, EPS or PostScript; with --stroke-only, each
    /// colour's outlines as lines. Without it, one shape is traced.
    #[arg(
        long,
        value_name = "auto|N",
        conflicts_with = "color",
        help_heading = "Colour"
    )]
    pub(crate) palette: Option<PaletteSize>,
    /// How colour layers are drawn: `stacked` (each colour extends under the ones drawn
    /// after it, so no seam can show) or `cutout` (regions abut exactly on their shared
    /// curves, for cutters and screen printing).
    #[arg(
        long,
        value_name = "stacked|cutout",
        default_value = "stacked",
        requires = "palette",
        help_heading = "Colour",
        hide_short_help = true
    )]
    pub(crate) layout: Layout,
}

impl ColourArgs {
    /// The colour options, or `None` for a one-colour trace. Refuses what a colour trace
    /// does not do: DXF and GeoJSON, and the research fits.
    pub(crate) fn options(
        &self,
        config: &Config,
        format: Format,
    ) -> anyhow::Result<Option<ColourOptions>> {
        let Some(palette) = self.palette else {
            return Ok(None);
        };
        if !matches!(format, Format::Svg | Format::Pdf | Format::Eps | Format::Ps) {
            bail!(
                "--palette writes SVG, PDF, EPS or PostScript; {} holds one colour (leave out --palette or choose another format)",
                format.name()
            );
        }
        if config.optimizer != Method::Lsq || config.merge || config.breaks != Default::default() {
            bail!("--palette fits with lsq; --optimizer, --merge and --breaks optimize are for one-colour traces");
        }
        Ok(Some(ColourOptions {
            palette,
            layout: self.layout,
        }))
    }
}

/// What is wrong with a colour trace's check, if it ran and did not hold.
pub(crate) fn colour_problem(config: &Config, trace: &ColourTrace) -> Option<String> {
    let f = &trace.fidelity;
    if !config.check || f.held {
        return None;
    }
    let at = f.region_box.map_or(String::new(), |[x0, y0, x1, y1]| {
        format!(" at pixels ({x0},{y0})-({x1},{y1})")
    });
    let colours = f.region_colours.map_or(String::new(), |[want, got]| {
        let name = |c: usize| {
            if c == 0 {
                "transparent".to_string()
            } else {
                trace.palette[c].hex()
            }
        };
        format!(" ({} drawn as {})", name(want), name(got))
    });
    Some(format!(
        "a region of {:.0} px² is drawn in the wrong colour{at}{colours}",
        f.largest_region
    ))
}

/// The warnings a colour trace deserves, one line each.
pub(crate) fn colour_warnings(name: &str, config: &Config, trace: &ColourTrace) -> Vec<String> {
    let mut out = Vec::new();
    if trace.layers.is_empty() {
        out.push(format!(
            "warning: {name}: the image is fully transparent; nothing is drawn"
        ));
    }
    if let Some(problem) = colour_problem(config, trace) {
        out.push(format!("warning: {name}: {problem}"));
    }
    let f = &trace.fidelity;
    if config.check && f.segments_over_tolerance > 0 {
        out.push(format!(
            "warning: {name}: {} segments lie farther than --tolerance {} px from their data (up to {:.2} px): too short to split",
            f.segments_over_tolerance, config.tolerance, f.max_deviation
        ));
    }
    out
}
