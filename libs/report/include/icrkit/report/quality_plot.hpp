#pragma once
/// \file
/// Fig. 8 as a figure: the cumulative Q_n histogram of eval::QualityHistogram
/// as a self-contained SVG and as a PNG rasterized with OpenCV, both drawn
/// from one layout so that the two files show the same plot.

#include <icrkit/eval/quality_histogram.hpp>

#include <string>
#include <vector>

namespace icrkit::report {

/// Looks of the plot; the defaults make a figure that reads like Fig. 8.
struct QualityPlotOptions {
  int width = 720;                           ///< pixels (SVG user units)
  int height = 440;
  std::string title;                         ///< empty: "Cumulative Q_n, N fingers"
  std::string raw_colour = "#e6550d";         ///< orange
  std::string filtered_colour = "#3182bd";    ///< blue
};

/// The title used when `options.title` is empty.
std::string qualityPlotTitle(const eval::QualityHistogram& histogram, const QualityPlotOptions& options = {});

/// A self-contained SVG document (no scripts, no external fonts).
std::string qualityHistogramSvg(const eval::QualityHistogram& histogram, const QualityPlotOptions& options = {});
/// The same plot rasterized with OpenCV, PNG-encoded.
std::vector<unsigned char> qualityHistogramPng(const eval::QualityHistogram& histogram,
                                               const QualityPlotOptions& options = {});

/// Atomic writers of the forms above.
void writeQualityHistogramSvg(const std::string& path, const eval::QualityHistogram& histogram,
                              const QualityPlotOptions& options = {});
void writeQualityHistogramPng(const std::string& path, const eval::QualityHistogram& histogram,
                              const QualityPlotOptions& options = {});

}  // namespace icrkit::report
