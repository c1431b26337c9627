// What an experiment shows first, stated by the experiment itself (Experiment::headline()): its curve's
// x column and the series drawn against it, the units each reads best in (the experiment's natural ones,
// e.g. p0 for a crystal, or SI), the summary values that answer its question, the summary tables worth a
// look, and the closed forms to draw beside the curve. The pictures, `granulab wait` and `sweep`, the
// sweep table and the web page (through GET /v1/experiments) read this and name no column themselves.
#pragma once

#include <string>
#include <vector>

namespace granulab {

/// How a stored value (SI) reads: times `factor`, then, when `per_field` is set, divided by the value of
/// that spec field (dotted, e.g. "loading.confining_pressure"), in `unit`.
struct Scale {
  double factor = 1;
  const char* unit = "-";
  const char* per_field = nullptr;
};

/// One axis, in the experiment's natural units or in SI units (the reader chooses).
struct Axis {
  const char* label;  ///< the quantity, without its unit, e.g. "axial strain"
  Scale natural, si;
};

/// A curve drawn against the x column: `column` in natural units, `si_column` (when another column holds
/// the same quantity in SI, e.g. P in N beside P / P0) or `column` again in SI units.
struct HeadlineSeries {
  const char* label;
  const char* column;
  const char* si_column = nullptr;
};

/// A summary value that answers the experiment's question, e.g. the first yield of a crystal.
struct KeyValue {
  const char* key;    ///< its dotted path in the summary, e.g. "first_yield.deviator_over_p0"
  const char* label;  ///< e.g. "first yield"
  const char* unit;   ///< as it reads, e.g. "p0"
  /// When it is a point of the curve: the dotted summary paths of its x and of its first series' value
  /// there (SI), where the picture marks it.
  const char* at_x = nullptr;
  const char* at_y = nullptr;
  /// When it may not exist (a first yield of a crystal that never yields): the dotted path of the summary group
  /// that says so, {"found": false, "reason": "none to 1 % strain (...)"} (curve_peak.h). Readers show the reason,
  /// never a number, where found is false.
  const char* status = nullptr;
};

/// A summary list of groups worth showing as a table, e.g. a crystal's load-unload cycles.
struct SummaryTable {
  const char* key;  ///< the list's key in the summary
  const char* title;
};

/// A closed form for these parameters, drawn dashed in the colour of series `series`.
struct ReferenceCurve {
  std::string label;
  std::size_t series = 0;
  std::vector<double> x;                ///< in the x axis' SI (= stored) values
  std::vector<double> y_natural, y_si;  ///< in the y axis' natural and SI units (already scaled)
};

/// Events of a run to mark along the curve's x axis: each element of the summary list `list` (a dotted path) at
/// its field `x` (in the x column's stored values), e.g. a crystal's stick-slip events.
struct EventMarks {
  const char* list = nullptr;
  const char* x = nullptr;
  const char* label = nullptr;
};

struct Headline {
  const char* x_column;
  Axis x;
  Axis y;                              ///< shared by every series
  std::vector<HeadlineSeries> series;  ///< the first is the one a sweep overlays and a watch line prints
  std::vector<KeyValue> values;
  std::vector<SummaryTable> tables;
  std::vector<ReferenceCurve> references;
  const char* note = nullptr;  ///< a line the picture adds, e.g. what a series includes
  EventMarks events;          ///< none by default
};

}  // namespace granulab
