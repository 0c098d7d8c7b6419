"""ParaView plugin: the "Boundary Particles" filter.

Load it in ParaView with Tools > Manage Plugins > Load New (this file), or in `pvpython` /
`pvbatch` with `LoadPlugin("BoundaryParticles.py", ns=globals())`. The filter takes any point
set (polydata, unstructured grid, the output of Table To Points) and adds the point arrays
`boundary` (1 on the boundary, 0 inside) and, when a phase array is chosen, `interface`; with
a wall array, `wall` (1 on the wall rows, whose `boundary` is 0). It runs on every time step
ParaView asks for, so an animated series is labelled frame by frame.

The filter only translates: it writes the points (and the chosen arrays) of the current time
step to a temporary VTK XML file, runs the `boundary` command line on it (`boundary detect ...
--output labels.vtp`) and copies the labels back. The detection runs in a process of its own,
so that no input can take ParaView down with it, and the command is the same whatever Python
ParaView was built with. It finds the command in the "Executable" property, else in the
environment variable BOUNDARY_CLI, else as `boundary` on PATH (`cargo install --path
crates/boundary-cli`).
"""

import os
import shutil
import subprocess
import tempfile

from paraview.util.vtkAlgorithm import smdomain, smhint, smproperty, smproxy
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import vtkOutputWindow
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPointSet, vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter

# The methods of `boundary methods`, in its order (a test checks the two agree).
METHODS = (
    "exact",
    "dilts",
    "ia",
    "ge",
    "marrone",
    "muller",
    "divr",
    "asymmetry",
    "randles",
    "lnm",
    "hpr",
    "svm",
)

# How r is given: the value of the "Resolution From" property, and the command-line flag.
RESOLUTION_FLAGS = {
    0: "--smoothing-length",
    1: "--spacing",
    2: "--radius",
    3: None,  # --radius auto
}

# The names the chosen input arrays get in the file handed to the command line, so that a
# name with spaces or commas needs no quoting there.
WALL_COLUMN = "wall_kind"
PHASE_COLUMN = "phase"

# The arrays the command line writes and the filter copies to its output.
LABEL_ARRAYS = ("boundary", "interface", "wall")


class BoundaryError(Exception):
    """A message for ParaView's output window: the filter fails, ParaView goes on."""


def _methods_xml():
    return "".join('<String value="{0}"/>'.format(m) for m in METHODS)


def _array_property(name, label, command, doc):
    """A point-array chooser on the first input, "None" by default."""
    return """
<StringVectorProperty name="{0}" label="{1}" command="{2}" number_of_elements="1"
    default_values="None">
  <ArrayListDomain name="array_list" none_string="None" attribute_type="Scalars"
      input_domain_name="input_array">
    <RequiredProperties><Property name="Input" function="Input"/></RequiredProperties>
  </ArrayListDomain>
  <Documentation>{3}</Documentation>
</StringVectorProperty>""".format(
        name, label, command, doc
    )


@smproxy.filter(name="BoundaryParticles", label="Boundary Particles")
@smhint.xml('<ShowInMenu category="Particles"/>')
@smproperty.xml(
    """
<InputProperty name="Walls" port_index="1" command="SetInputConnection">
  <ProxyGroupDomain name="groups"><Group name="sources"/><Group name="filters"/></ProxyGroupDomain>
  <DataTypeDomain name="input_type"><DataType value="vtkPointSet"/></DataTypeDomain>
  <Hints><Optional/></Hints>
  <Documentation>Optional wall particles: they cover the particles of the input and get
  no label (the command line's --walls).</Documentation>
</InputProperty>"""
)
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkPointSet"], composite_data_supported=False)
class BoundaryParticles(VTKPythonAlgorithmBase):
    """Labels the boundary particles of a point set with the `boundary` command line."""

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=2, nOutputPorts=1)
        self._method = "exact"
        self._parameters = ""
        self._resolution_from = 3
        self._value = 0.0
        self._dimension = 0
        self._band = 0
        self._wall_array = "None"
        self._wall_values = "0"
        self._phase_array = "None"
        self._threads = 0
        self._executable = ""

    # The pipeline ---------------------------------------------------------------------

    def FillInputPortInformation(self, port, info):
        info.Set(self.INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet")
        if port == 1:
            info.Set(self.INPUT_IS_OPTIONAL(), 1)
        return 1

    def RequestDataObject(self, request, inInfo, outInfo):
        """The output has the input's type (polydata in, polydata out)."""
        source = inInfo[0].GetInformationObject(0).Get(vtkDataObject.DATA_OBJECT())
        if source is None:
            return 0
        out = outInfo.GetInformationObject(0)
        current = out.Get(vtkDataObject.DATA_OBJECT())
        if current is None or not current.IsA(source.GetClassName()):
            out.Set(vtkDataObject.DATA_OBJECT(), source.NewInstance())
        return 1

    def RequestData(self, request, inInfo, outInfo):
        source = vtkPointSet.GetData(inInfo[0])
        output = vtkPointSet.GetData(outInfo)
        output.ShallowCopy(source)
        walls = None
        if inInfo[1].GetNumberOfInformationObjects() > 0:
            walls = vtkPointSet.GetData(inInfo[1])
        try:
            labels = self._label(source, walls)
        except BoundaryError as e:
            vtkOutputWindow.GetInstance().DisplayErrorText(
                "Boundary Particles: {0}\n".format(e)
            )
            return 0
        for array in labels:
            output.GetPointData().AddArray(array)
        if labels:
            output.GetPointData().SetActiveScalars("boundary")
        return 1

    # Translation to and from the command line -----------------------------------------

    def _command(self):
        exe = self._executable.strip() or os.environ.get("BOUNDARY_CLI", "").strip()
        if exe:
            if os.path.isfile(exe) and os.access(exe, os.X_OK):
                return exe
            found = shutil.which(exe)
            if found:
                return found
            raise BoundaryError(
                "the executable {0!r} (property Executable or BOUNDARY_CLI) is not a "
                "program".format(exe)
            )
        found = shutil.which("boundary")
        if found is None:
            raise BoundaryError(
                "the `boundary` command line is not on PATH: install it with `cargo "
                "install --path crates/boundary-cli`, or give its path in the Executable "
                "property or in BOUNDARY_CLI"
            )
        return found

    def _point_array(self, source, name, what):
        array = source.GetPointData().GetArray(name)
        if array is None:
            raise BoundaryError(
                "the {0} array {1!r} is not a point array of the input".format(what, name)
            )
        if array.GetNumberOfComponents() != 1:
            raise BoundaryError(
                "the {0} array {1!r} has {2} components; it needs one".format(
                    what, name, array.GetNumberOfComponents()
                )
            )
        return array

    def _write(self, path, points_of, arrays):
        """The points of `points_of` and `arrays` (name, array) as a VTK XML PolyData file:
        binary, raw appended, uncompressed, the points in their own precision."""
        data = vtkPolyData()
        data.SetPoints(points_of.GetPoints())
        for name, array in arrays:
            copy = array.NewInstance()
            copy.ShallowCopy(array)
            copy.SetName(name)
            data.GetPointData().AddArray(copy)
        writer = vtkXMLPolyDataWriter()
        writer.SetInputData(data)
        writer.SetFileName(path)
        writer.SetDataModeToAppended()
        writer.EncodeAppendedDataOff()
        writer.SetCompressorTypeToNone()
        writer.SetHeaderTypeToUInt64()
        if writer.Write() != 1:
            raise BoundaryError("cannot write the points to {0}".format(path))

    def _arguments(self, exe, points, walls, output):
        args = [exe, "detect", points, "--output", output, "--method", self._method]
        for setting in self._parameters.split():
            args += ["--set", setting]
        flag = RESOLUTION_FLAGS.get(self._resolution_from)
        if flag is None:
            args += ["--radius", "auto"]
        else:
            if not self._value > 0.0:
                raise BoundaryError(
                    "set Value to the {0} (it is {1})".format(
                        flag.lstrip("-").replace("-", " "), self._value
                    )
                )
            args += [flag, repr(float(self._value))]
        if self._dimension in (2, 3):
            args += ["--dim", str(self._dimension)]
        if self._band > 0:
            args += ["--band", str(self._band)]
        if self._threads > 0:
            args += ["--threads", str(self._threads)]
        if walls is not None:
            args += ["--walls", walls]
        if self._wall_array != "None":
            values = self._wall_values.replace(" ", "")
            args += ["--wall-attribute", "{0}={1}".format(WALL_COLUMN, values)]
        if self._phase_array != "None":
            args += ["--phase-attribute", PHASE_COLUMN]
        return args

    def _label(self, source, walls):
        """The label arrays of `source` (with the optional wall set `walls`), in its order."""
        n = source.GetNumberOfPoints()
        if n == 0:
            return []
        exe = self._command()
        arrays = []
        if self._wall_array != "None":
            arrays.append((WALL_COLUMN, self._point_array(source, self._wall_array, "wall")))
        if self._phase_array != "None":
            arrays.append(
                (PHASE_COLUMN, self._point_array(source, self._phase_array, "phase"))
            )
        with tempfile.TemporaryDirectory(prefix="boundary-paraview-") as folder:
            points = os.path.join(folder, "points.vtp")
            labelled = os.path.join(folder, "labels.vtp")
            self._write(points, source, arrays)
            walls_path = None
            if walls is not None and walls.GetNumberOfPoints() > 0:
                walls_path = os.path.join(folder, "walls.vtp")
                self._write(walls_path, walls, [])
            args = self._arguments(exe, points, walls_path, labelled)
            try:
                run = subprocess.run(
                    args,
                    stdout=subprocess.PIPE,
                    stderr=subprocess.PIPE,
                    stdin=subprocess.DEVNULL,
                    check=False,
                )
            except OSError as e:
                raise BoundaryError("cannot run {0}: {1}".format(exe, e))
            # The command's messages name the temporary files: name the inputs instead.
            message = run.stderr.decode("utf-8", "replace").strip()
            message = message.replace(points, "the input").replace(labelled, "the output")
            if walls_path is not None:
                message = message.replace(walls_path, "the Walls input")
            message = message.replace("--dim 2", "--dim 2 (the filter's Dimension: 2D)")
            if run.returncode != 0:
                raise BoundaryError(
                    "`boundary detect` failed ({0}): {1}".format(
                        _status(run.returncode), message or "no message"
                    )
                )
            if message:
                # The summary line: counts, what was read, and the r chosen.
                vtkOutputWindow.GetInstance().DisplayText(
                    "Boundary Particles: {0}\n".format(message)
                )
            reader = vtkXMLPolyDataReader()
            reader.SetFileName(labelled)
            reader.Update()
            result = reader.GetOutput()
            if result.GetNumberOfPoints() != n:
                raise BoundaryError(
                    "`boundary detect` wrote {0} labels for {1} points".format(
                        result.GetNumberOfPoints(), n
                    )
                )
            labels = []
            for name in LABEL_ARRAYS:
                array = result.GetPointData().GetArray(name)
                if array is not None:
                    labels.append(array)
            if not labels:
                raise BoundaryError("`boundary detect` wrote no `boundary` array")
            return labels

    # Properties (shown in the panel in this order, the inputs first) ------------------

    @smproperty.xml(
        """
<StringVectorProperty name="Method" command="SetMethod" number_of_elements="1"
    default_values="exact">
  <StringListDomain name="list">{0}</StringListDomain>
  <Documentation>The detection method (`boundary methods` lists them; exact by
  default).</Documentation>
</StringVectorProperty>""".format(
            _methods_xml()
        )
    )
    def SetMethod(self, method):
        method = method or "exact"
        if method != self._method:
            self._method = method
            self.Modified()

    @smproperty.stringvector(name="Parameters", default_values="")
    @smdomain.xml(
        "<Documentation>The method's parameters as key=value, separated by spaces (the "
        "command line's --set), e.g. tie=1e-9.</Documentation>"
    )
    def SetParameters(self, parameters):
        parameters = parameters or ""
        if parameters != self._parameters:
            self._parameters = parameters
            self.Modified()

    @smproperty.xml(
        """
<IntVectorProperty name="ResolutionFrom" label="Resolution From" command="SetResolutionFrom"
    number_of_elements="1" default_values="3">
  <EnumerationDomain name="enum">
    <Entry value="0" text="Smoothing length h"/>
    <Entry value="1" text="Particle spacing"/>
    <Entry value="2" text="Radius r"/>
    <Entry value="3" text="Auto (estimated spacing)"/>
  </EnumerationDomain>
  <Documentation>How r is given: the solver's smoothing length h (r = h), the particle
  spacing (r = 1.45 x spacing), r itself, or estimated from the set.</Documentation>
</IntVectorProperty>"""
    )
    def SetResolutionFrom(self, value):
        if value != self._resolution_from:
            self._resolution_from = value
            self.Modified()

    @smproperty.doublevector(name="Value", default_values=0.0)
    @smdomain.xml(
        "<Documentation>The smoothing length, spacing or radius (not used by Auto)."
        "</Documentation>"
    )
    def SetValue(self, value):
        if value != self._value:
            self._value = value
            self.Modified()

    @smproperty.xml(
        """
<IntVectorProperty name="Dimension" command="SetDimension" number_of_elements="1"
    default_values="0">
  <EnumerationDomain name="enum">
    <Entry value="0" text="As stored"/>
    <Entry value="2" text="2D (drop the constant axis)"/>
    <Entry value="3" text="3D"/>
  </EnumerationDomain>
  <Documentation>A 2D scene stored with a constant z (or y) is flat: choose 2D.
  </Documentation>
</IntVectorProperty>"""
    )
    def SetDimension(self, value):
        if value != self._dimension:
            self._dimension = value
            self.Modified()

    @smproperty.xml(
        _array_property(
            "WallArray",
            "Wall Array",
            "SetWallArray",
            "A point array whose values in Wall Values mark wall rows (DualSPHysics: "
            "Type with 0,1,2).",
        )
    )
    def SetWallArray(self, name):
        name = name or "None"
        if name != self._wall_array:
            self._wall_array = name
            self.Modified()

    @smproperty.stringvector(name="WallValues", label="Wall Values", default_values="0")
    @smdomain.xml(
        "<Documentation>The values of Wall Array that mark walls, separated by commas."
        "</Documentation>"
    )
    def SetWallValues(self, values):
        values = values or ""
        if values != self._wall_values:
            self._wall_values = values
            self.Modified()

    @smproperty.xml(
        _array_property(
            "PhaseArray",
            "Phase Array",
            "SetPhaseArray",
            "A point array of phase numbers: adds the interface array.",
        )
    )
    def SetPhaseArray(self, name):
        name = name or "None"
        if name != self._phase_array:
            self._phase_array = name
            self.Modified()

    @smproperty.intvector(name="Band", default_values=0)
    @smdomain.intrange(min=0, max=10)
    def SetBand(self, band):
        if band != self._band:
            self._band = band
            self.Modified()

    @smproperty.intvector(name="Threads", default_values=0)
    @smdomain.xml("<Documentation>Threads of the detection; 0 for all cores.</Documentation>")
    def SetThreads(self, threads):
        if threads != self._threads:
            self._threads = threads
            self.Modified()

    @smproperty.stringvector(name="Executable", default_values="")
    @smdomain.xml(
        "<Documentation>The `boundary` command line; empty for BOUNDARY_CLI or `boundary` "
        "on PATH.</Documentation>"
    )
    def SetExecutable(self, path):
        path = path or ""
        if path != self._executable:
            self._executable = path
            self.Modified()


def _status(code):
    if code < 0:
        return "killed by signal {0}".format(-code)
    return "exit status {0}".format(code)
