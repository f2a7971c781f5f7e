#include "views/vtk_parts.h"

#include <vtkActor.h>
#include <vtkAlgorithmOutput.h>
#include <vtkArrowSource.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyLine.h>
#include <vtkProperty.h>
#include <vtkTable.h>
#include <vtkTransform.h>

#include <Eigen/Geometry>
#include <utility>

namespace roverlab::views {

namespace {

vtkSmartPointer<vtkActor> actor_with(vtkPolyDataMapper* mapper, const Eigen::Vector3d& rgb) {
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb.x(), rgb.y(), rgb.z());
  return actor;
}

void unlit_line(vtkActor* actor, double width) {
  actor->GetProperty()->SetLineWidth(static_cast<float>(width));
  actor->GetProperty()->SetLighting(false);
}

}  // namespace

vtkSmartPointer<vtkActor> actor_of(vtkAlgorithmOutput* port, const Eigen::Vector3d& rgb) {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(port);
  return actor_with(mapper, rgb);
}

vtkSmartPointer<vtkActor> unlit_arrow(const Eigen::Vector3d& rgb, double shaft_radius, double tip_radius,
                                      double tip_length, int resolution) {
  vtkNew<vtkArrowSource> src;
  src->SetShaftRadius(shaft_radius);
  src->SetTipRadius(tip_radius);
  src->SetTipLength(tip_length);
  src->SetShaftResolution(resolution);
  src->SetTipResolution(resolution);
  auto a = actor_of(src->GetOutputPort(), rgb);
  a->GetProperty()->SetLighting(false);
  return a;
}

vtkSmartPointer<vtkActor> actor_of(vtkPolyData* data, const Eigen::Vector3d& rgb) {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(data);
  return actor_with(mapper, rgb);
}

void place_arrow(vtkActor* actor, const Eigen::Vector3d& from, const Eigen::Vector3d& direction, double length) {
  const Eigen::Vector3d x = direction.normalized();
  const Eigen::Vector3d y = x.unitOrthogonal();
  const Eigen::Vector3d z = x.cross(y);
  vtkNew<vtkMatrix4x4> m;
  for (int r = 0; r < 3; ++r) {
    m->SetElement(r, 0, x[r] * length);
    m->SetElement(r, 1, y[r] * length);
    m->SetElement(r, 2, z[r] * length);
    m->SetElement(r, 3, from[r]);
  }
  vtkNew<vtkTransform> t;
  t->SetMatrix(m);
  actor->SetUserTransform(t);
}

vtkSmartPointer<vtkPolyData> polyline(const std::vector<Eigen::Vector3d>& points) {
  vtkNew<vtkPoints> pts;
  vtkNew<vtkPolyLine> line;
  for (const auto& p : points) line->GetPointIds()->InsertNextId(pts->InsertNextPoint(p.x(), p.y(), p.z()));
  vtkNew<vtkCellArray> cells;
  cells->InsertNextCell(line);
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetLines(cells);
  return poly;
}

vtkSmartPointer<vtkPolyData> segments(const std::vector<Eigen::Vector3d>& points, bool pairs) {
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> cells;
  for (const auto& p : points) pts->InsertNextPoint(p.x(), p.y(), p.z());
  const vtkIdType n = pts->GetNumberOfPoints();
  for (vtkIdType a = 0; a + 1 < n; a += pairs ? 2 : 1) {
    const vtkIdType ids[2] = {a, a + 1};
    cells->InsertNextCell(2, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetLines(cells);
  return poly;
}

vtkSmartPointer<vtkPolyData> legend_swatch() {
  vtkNew<vtkPoints> pts;
  for (const auto& [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}}) pts->InsertNextPoint(x, y, 0.0);
  vtkNew<vtkCellArray> cells;
  const vtkIdType ids[4] = {0, 1, 2, 3};
  cells->InsertNextCell(4, ids);
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetPolys(cells);
  return poly;
}

vtkSmartPointer<vtkActor> line_actor(vtkPolyData* lines, const Eigen::Vector3d& rgb, double width) {
  auto actor = actor_of(lines, rgb);
  unlit_line(actor, width);
  return actor;
}

vtkSmartPointer<vtkActor> line_actor(vtkAlgorithmOutput* port, const Eigen::Vector3d& rgb, double width) {
  auto actor = actor_of(port, rgb);
  unlit_line(actor, width);
  return actor;
}

vtkSmartPointer<vtkTable> table_of(const std::vector<std::pair<const char*, std::vector<double>>>& columns) {
  auto table = vtkSmartPointer<vtkTable>::New();
  for (const auto& [name, values] : columns) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
    for (std::size_t i = 0; i < values.size(); ++i) a->SetValue(static_cast<vtkIdType>(i), values[i]);
    table->AddColumn(a);
  }
  return table;
}

void move_cursor(vtkTable* cursor, double t, const std::pair<double, double>& range) {
  cursor->SetValue(0, 0, t);
  cursor->SetValue(1, 0, t);
  cursor->SetValue(0, 1, range.first);
  cursor->SetValue(1, 1, range.second);
  cursor->Modified();
}

}  // namespace roverlab::views
