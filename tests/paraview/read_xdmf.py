"""Open a file with ParaView's default reader and describe what it read, for tests/paraview.rs.

usage: pvpython read_xdmf.py FILE

Prints `reader<TAB>NAME`, then for every time step (or once, for a file without time) and
every leaf block (numbered in order):
  block<TAB>time<TAB>index<TAB>points<TAB>cells<TAB>point arrays<TAB>cell arrays<TAB>bounds
      (arrays comma-separated as `name:components`; bounds `xmin xmax ymin ymax zmin zmax`)
  array<TAB>time<TAB>index<TAB>point|cell<TAB>name<TAB>sum<TAB>first
      (sum of the finite values of all components; first: the first tuple, space-separated)
  point0<TAB>time<TAB>index<TAB>x y z   (coordinates of the first point)
"""
import math
import sys

from paraview import servermanager as sm
from paraview.simple import OpenDataFile

path = sys.argv[1]
reader = OpenDataFile(path)
if reader is None:
    sys.exit(f"ParaView has no reader for {path}")
print(f"reader\t{reader.GetXMLName()}")
times = list(getattr(reader, "TimestepValues", []) or []) or [None]


def names(data):
    return ",".join(
        f"{data.GetArrayName(i)}:{data.GetArray(i).GetNumberOfComponents()}"
        for i in range(data.GetNumberOfArrays())
    )


def leaves(d):
    if d is None:
        return
    if d.IsA("vtkMultiBlockDataSet"):
        for i in range(d.GetNumberOfBlocks()):
            yield from leaves(d.GetBlock(i))
    elif d.IsA("vtkMultiPieceDataSet"):
        for i in range(d.GetNumberOfPieces()):
            yield from leaves(d.GetPiece(i))
    else:
        yield d


def describe(t, k, kind, data):
    for i in range(data.GetNumberOfArrays()):
        a = data.GetArray(i)
        total = 0.0
        for j in range(a.GetNumberOfTuples()):
            for c in range(a.GetNumberOfComponents()):
                v = a.GetComponent(j, c)
                if math.isfinite(v):
                    total += v
        first = " ".join(repr(a.GetComponent(0, c)) for c in range(a.GetNumberOfComponents()))
        print(f"array\t{t!r}\t{k}\t{kind}\t{a.GetName()}\t{total!r}\t{first}")


for t in times:
    if t is None:
        reader.UpdatePipeline()
    else:
        reader.UpdatePipeline(t)
    for k, d in enumerate(leaves(sm.Fetch(reader))):
        bounds = " ".join(repr(b) for b in d.GetBounds())
        print(
            f"block\t{t!r}\t{k}\t{d.GetNumberOfPoints()}\t{d.GetNumberOfCells()}\t"
            f"{names(d.GetPointData())}\t{names(d.GetCellData())}\t{bounds}"
        )
        describe(t, k, "point", d.GetPointData())
        describe(t, k, "cell", d.GetCellData())
        if d.GetNumberOfPoints() > 0:
            print(f"point0\t{t!r}\t{k}\t" + " ".join(repr(x) for x in d.GetPoint(0)))
