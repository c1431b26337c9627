// The spec fields shared by every experiment built from grains of one template and one material: the
// "grain" and "material" sections, and the engine knobs of the "run" section (see
// engine/framework/parameters.h for how fields are visited).
#pragma once

#include <string>
#include <vector>

#include "engine/framework/parameters.h"
#include "engine/geometry/grain_template.h"
#include "engine/model/model.h"

namespace granulab {

/// The "grain" section. `g.shape` is the experiment's shape: a spec may name it, not change it; `shapes` lists
/// what the field can be named (default: g.shape alone), a name other than g.shape is refused naming it.
void visit_grain(ParameterVisitor& v, GrainGeometry& g, const std::vector<Shape>& shapes = {},
                 const std::string& why = "");
/// The "material" section, then the "contact" section (visit_interface_law).
void visit_material(ParameterVisitor& v, Material& m);
/// The "contact" section: the interface law's models and their parameters.
void visit_interface_law(ParameterVisitor& v, Material& m);
/// The engine knobs of the "run" section: dt / t0 and the neighbour skin / d.
/// The run's integration: time step, skin, and the contact kernel's instruction set (refused, naming run.kernel, where
/// this CPU lacks it).
void visit_integration(ParameterVisitor& v, double& time_step_factor, double& skin_factor, std::string& kernel);

}  // namespace granulab
