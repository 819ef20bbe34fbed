// Histograms as inline SVG drawn by lsds itself: the page needs no charting
// library and opens offline.
#pragma once

#include <string>

#include "report/histogram.h"
#include "report/html_text.h"

namespace lsds::report {

// A bar chart with a count axis (left), the bins' edges or names (bottom), the
// x label with its unit, and a tooltip per bar. Numeric histograms show the
// bins from the first to the last non-empty one, plus "<" and ">" bars for
// values outside the bins when there are any. Warning bins (Histogram::
// warn_below) are drawn in red.
Html HistogramSvg(const Histogram& histogram, int width = 380, int height = 230);

// Short numbers for axes and legends: FormatAxisNumber (libs/util/strings.h).

}  // namespace lsds::report
