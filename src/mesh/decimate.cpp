#include "mesh/decimate.h"

#include "mesh/error.h"

#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkDecimatePro.h>

#include <algorithm>

namespace vesselmesh::mesh {

TriMesh decimated(const TriMesh& surface, int max_triangles) {
  VM_CHECK(max_triangles > 0, "decimated: a positive triangle count");
  if (surface.num_triangles() <= max_triangles) return surface;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(surface.num_points());
  for (int i = 0; i < surface.num_points(); ++i) points->SetPoint(i, surface.points[i].data());
  vtkNew<vtkCellArray> cells;
  for (const Triangle& t : surface.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    cells->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> input;
  input->SetPoints(points);
  input->SetPolys(cells);
  // The filter stops near its target, not always under it: aimed a little under, and again lower
  // when it overshoots.
  double keep = 0.97 * max_triangles / static_cast<double>(surface.num_triangles());
  TriMesh result;
  for (int attempt = 0; attempt < 4; ++attempt) {
    vtkNew<vtkDecimatePro> filter;  // (VTK's quadric decimation took 13 s on a 131k-triangle pipe, this 0.6)
    filter->SetInputData(input);
    filter->SetTargetReduction(std::clamp(1.0 - keep, 0.0, 0.999));
    filter->SetPreserveTopology(attempt < 3);  // the last attempt may split the mesh to reach the count
    filter->BoundaryVertexDeletionOff();  // the open ends' rims stay as they are
    filter->Update();
    vtkPolyData* out = filter->GetOutput();
    result = TriMesh{};
    result.points.resize(static_cast<size_t>(out->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) out->GetPoint(i, result.points[i].data());
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c) {
      out->GetCellPoints(c, ids);
      if (ids->GetNumberOfIds() == 3)
        result.triangles.push_back({static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(1)),
                                    static_cast<int>(ids->GetId(2))});
    }
    if (result.num_triangles() <= max_triangles) break;
    keep *= 0.97 * max_triangles / static_cast<double>(result.num_triangles());
  }
  return result;
}

}  // namespace vesselmesh::mesh
