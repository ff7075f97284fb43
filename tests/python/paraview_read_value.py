"""Run with pvbatch (Debian package paraview): opens a mode-shape VTU with ParaView's own reader and
prints one nodal value with 17 digits. Usage: pvbatch paraview_read_value.py FILE.vtu ARRAY INDEX"""
import sys

from paraview import servermanager
from paraview.simple import XMLUnstructuredGridReader

reader = XMLUnstructuredGridReader(FileName=[sys.argv[1]])
reader.UpdatePipeline()
data = servermanager.Fetch(reader)
array = data.GetPointData().GetArray(sys.argv[2])
print("VALUE %.17g %.17g %.17g" % array.GetTuple3(int(sys.argv[3])))
