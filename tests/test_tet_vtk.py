"""Reads cw4d's .vtu tetrahedral meshes with VTK's own XML reader (run by CTest with the system
python3, which has python3-vtk9): cw4d tetrahedralize MODEL -o x.vtu, ASCII and --binary.

usage: test_tet_vtk.py CW4D_EXE MODEL EXPECTED_TETRAHEDRA EXPECTED_SOURCE_CELLS
"""
import os
import subprocess
import sys
import tempfile

import vtk


def check(exe, model, tets, cells, binary):
    with tempfile.TemporaryDirectory(prefix="cw4d_vtk_") as d:
        path = os.path.join(d, "mesh.vtu")
        cmd = [exe, "tetrahedralize", model, "-o", path] + (["--binary"] if binary else [])
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        if reader.GetErrorCode() != 0:
            raise SystemExit(f"{model}: VTK reports error {reader.GetErrorCode()}")
        grid = reader.GetOutput()
        what = f"{model} ({'binary' if binary else 'ascii'})"
        assert grid.GetNumberOfCells() == tets, f"{what}: {grid.GetNumberOfCells()} cells, expected {tets}"
        assert grid.GetNumberOfPoints() == 4 * tets, f"{what}: {grid.GetNumberOfPoints()} points"
        for i in range(grid.GetNumberOfCells()):
            assert grid.GetCellType(i) == vtk.VTK_TETRA, f"{what}: cell {i} is type {grid.GetCellType(i)}"
        pd = grid.GetPointData()
        for name, comps in (("position4", 4), ("normal4", 4), ("uvw", 3)):
            arr = pd.GetArray(name)
            assert arr is not None, f"{what}: no point array {name}"
            assert arr.GetNumberOfComponents() == comps, f"{what}: {name} has {arr.GetNumberOfComponents()}"
            assert arr.GetNumberOfTuples() == 4 * tets
        # The points are the Schlegel diagram: every tetrahedron has a positive volume as VTK
        # measures it, and the cells behind the front cell tile the front cell's image.
        quality = vtk.vtkMeshQuality()
        quality.SetInputData(grid)
        quality.SetTetQualityMeasureToVolume()
        quality.Update()
        volumes = quality.GetOutput().GetCellData().GetArray("Quality")
        front = grid.GetCellData().GetArray("front")
        assert front is not None and front.GetNumberOfTuples() == tets, f"{what}: no cell data 'front'"
        sums = [0.0, 0.0]
        for i in range(tets):
            v = volumes.GetValue(i)
            assert v > 0, f"{what}: tetrahedron {i} has volume {v}"
            sums[int(front.GetValue(i))] += v
        assert sums[1] > 0 and abs(sums[0] - sums[1]) <= 1e-9 * sums[1], f"{what}: volumes {sums}"
        normals = pd.GetArray("normal4")
        for i in range(0, grid.GetNumberOfPoints(), 89):
            n = normals.GetTuple4(i)
            assert abs(sum(x * x for x in n) - 1.0) < 1e-9, f"{what}: normal {i} not unit"
        cell = grid.GetCellData().GetArray("cell")
        assert cell is not None and cell.GetNumberOfTuples() == tets, f"{what}: no cell data 'cell'"
        lo, hi = cell.GetRange()
        assert lo == 0 and hi == cells - 1, f"{what}: source cells {lo}..{hi}, expected 0..{cells - 1}"
        print(f"{what}: VTK read {tets} tetrahedra of {cells} cells")


def main():
    exe, model, tets, cells = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    check(exe, model, tets, cells, binary=False)
    check(exe, model, tets, cells, binary=True)


if __name__ == "__main__":
    main()
