// The vtk writer plugin (libvtkWriter.so; the library is not named libvtk.so so that it
// cannot be mistaken for, or shadow, a VTK library).
#include "VtkWriter.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_writer<scree::vtkio::VtkWriter>(); }
