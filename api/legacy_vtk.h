// Legacy ASCII VTK files: their cells, and the arrays beyond its first SCALARS and first VECTORS, as one FIELD block. VTK's
// legacy readers keep only the first SCALARS and the first VECTORS of a POINT_DATA or CELL_DATA section unless told
// to read them all (with vtkDataSetReader's defaults a Python script saw 3 of a grain file's 10 arrays); ParaView
// reads them all. Every one of them reads a FIELD block's arrays, so every array after the first scalar and vector
// goes there. Values are written as given: the callers write only finite numbers (a standard reader stops at "nan"
// and still reports success).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace granulab::api {

// The cell kinds of an UNSTRUCTURED_GRID that the exports use (VTK's cell type numbers). No VTK_POLYGON: meshio reads
// a file with one but drops all its cell data, so a face of more than 4 corners is written as triangles.
enum class VtkCell { vertex = 1, line = 3, triangle = 5, quad = 9 };

/// The cells of an UNSTRUCTURED_GRID: "CELLS <count> <size>", `connectivity` (a line per cell: its point count,
/// then its points), and "CELL_TYPES" with each cell's type (`types`, one per cell). Every legacy reader reads this
/// dataset (VTK, ParaView, and meshio, which refuses POLYDATA).
inline void append_cells(std::string& out, std::size_t size, const std::string& connectivity,
                         const std::vector<VtkCell>& types) {
  out += "CELLS " + std::to_string(types.size()) + " " + std::to_string(size) + "\n";
  out += connectivity;
  out += "CELL_TYPES " + std::to_string(types.size()) + "\n";
  for (VtkCell t : types) out += std::to_string(int(t)) + "\n";
}

/// The same with one type for all `count` cells.
inline void append_cells(std::string& out, std::size_t count, std::size_t size, const std::string& connectivity,
                         VtkCell type) {
  append_cells(out, size, connectivity, std::vector<VtkCell>(count, type));
}

class VtkFieldBlock {
 public:
  /// An array of `tuples` tuples of `components` numbers each; `values` is their text, whitespace separated
  /// (e.g. a tuple a line).
  void add(std::string name, int components, std::size_t tuples, std::string values) {
    arrays_.push_back({std::move(name), components, tuples, std::move(values)});
  }
  /// Appends "FIELD <name> <arrays>" and each array's header and values to `out`; nothing when no array was added.
  void append_to(std::string& out, const char* name) const {
    if (arrays_.empty()) return;
    out += std::string("FIELD ") + name + " " + std::to_string(arrays_.size()) + "\n";
    for (const Array& a : arrays_) {
      out += a.name + " " + std::to_string(a.components) + " " + std::to_string(a.tuples) + " double\n";
      out += a.values;
    }
  }

 private:
  struct Array {
    std::string name;
    int components;
    std::size_t tuples;
    std::string values;
  };
  std::vector<Array> arrays_;
};

}  // namespace granulab::api
