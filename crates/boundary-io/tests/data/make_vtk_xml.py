"""Makes the VTK XML test files of this folder with VTK itself (pip install vtk; run once,
the outputs are committed; the tests do not run this script).

12 particles, index i = 0..11:
  position  (0.5 * (i % 3), 0.25 * ((i // 3) % 2), 0.125 * (i // 6))   Float32 or Float64
  velocity  (i, -i, 0.5 * i)                                            Float32, 3 components
  density   1000 + i / 8                                                Float64
  id        100 + i                                                     Int32
  type      i % 2                                                       UInt8
All values are exact in Float32, so the tests compare with ==.
"""
import vtk

N = 12


def arrays():
    points = vtk.vtkPoints()
    velocity = vtk.vtkFloatArray()
    velocity.SetName("velocity")
    velocity.SetNumberOfComponents(3)
    density = vtk.vtkDoubleArray()
    density.SetName("density")
    ident = vtk.vtkIntArray()
    ident.SetName("id")
    kind = vtk.vtkUnsignedCharArray()
    kind.SetName("type")
    for i in range(N):
        points.InsertNextPoint(0.5 * (i % 3), 0.25 * ((i // 3) % 2), 0.125 * (i // 6))
        velocity.InsertNextTuple3(i, -i, 0.5 * i)
        density.InsertNextValue(1000 + i / 8)
        ident.InsertNextValue(100 + i)
        kind.InsertNextValue(i % 2)
    return points, [velocity, density, ident, kind]


def polydata(double):
    points, data = arrays()
    if double:
        p = vtk.vtkPoints()
        p.SetDataTypeToDouble()
        for i in range(N):
            p.InsertNextPoint(points.GetPoint(i))
        points = p
    verts = vtk.vtkCellArray()
    for i in range(N):
        verts.InsertNextCell(1)
        verts.InsertCellPoint(i)
    pd = vtk.vtkPolyData()
    pd.SetPoints(points)
    pd.SetVerts(verts)
    for a in data:
        pd.GetPointData().AddArray(a)
    return pd


def grid(double):
    pd = polydata(double)
    ug = vtk.vtkUnstructuredGrid()
    ug.SetPoints(pd.GetPoints())
    ug.Allocate(N)
    for i in range(N):
        ids = vtk.vtkIdList()
        ids.InsertNextId(i)
        ug.InsertNextCell(vtk.VTK_VERTEX, ids)
    for k in range(pd.GetPointData().GetNumberOfArrays()):
        ug.GetPointData().AddArray(pd.GetPointData().GetArray(k))
    return ug


def write(writer, data, name, mode, compress=False, header64=True, big=False, encode=False):
    writer.SetInputData(data)
    writer.SetFileName(name)
    if mode == "ascii":
        writer.SetDataModeToAscii()
    elif mode == "binary":
        writer.SetDataModeToBinary()
    else:
        writer.SetDataModeToAppended()
        writer.SetEncodeAppendedData(1 if encode else 0)
    if compress:
        writer.SetCompressorTypeToZLib()
        writer.SetBlockSize(64)  # several blocks per array
    else:
        writer.SetCompressorTypeToNone()
    if header64:
        writer.SetHeaderTypeToUInt64()
    else:
        writer.SetHeaderTypeToUInt32()
    if big:
        writer.SetByteOrderToBigEndian()
    else:
        writer.SetByteOrderToLittleEndian()
    assert writer.Write() == 1


write(vtk.vtkXMLUnstructuredGridWriter(), grid(False), "grid_ascii.vtu", "ascii")
write(vtk.vtkXMLUnstructuredGridWriter(), grid(True), "grid_binary.vtu", "binary", header64=False)
write(vtk.vtkXMLUnstructuredGridWriter(), grid(False), "grid_appended_raw.vtu", "appended")
write(vtk.vtkXMLUnstructuredGridWriter(), grid(True), "grid_appended_zlib.vtu", "appended", compress=True)
write(vtk.vtkXMLUnstructuredGridWriter(), grid(False), "grid_binary_zlib_be.vtu", "binary", compress=True, header64=False, big=True)
write(vtk.vtkXMLPolyDataWriter(), polydata(False), "poly_ascii.vtp", "ascii")
write(vtk.vtkXMLPolyDataWriter(), polydata(True), "poly_binary_zlib.vtp", "binary", compress=True)
write(vtk.vtkXMLPolyDataWriter(), polydata(False), "poly_appended_base64.vtp", "appended", encode=True, header64=False)
write(vtk.vtkXMLPolyDataWriter(), polydata(True), "poly_appended_raw_be.vtp", "appended", big=True)
print(vtk.vtkVersion.GetVTKVersion())

# Legacy VTK (.vtk) from the same data, as VTK 9 writes it (version 5.1: OFFSETS and
# CONNECTIVITY, METADATA blocks); read by the legacy reader's POINT_DATA walk.
for mode, name in [("ascii", "poly_legacy_ascii.vtk"), ("binary", "grid_legacy_binary.vtk")]:
    w = vtk.vtkPolyDataWriter() if mode == "ascii" else vtk.vtkUnstructuredGridWriter()
    w.SetInputData(polydata(False) if mode == "ascii" else grid(True))
    w.SetFileName(name)
    if mode == "ascii":
        w.SetFileTypeToASCII()
    else:
        w.SetFileTypeToBinary()
    assert w.Write() == 1
