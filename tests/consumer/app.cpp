// Reads a mesh with the installed library, certifies it, and solves a small SPD system.
#include <cstdio>

#include <Eigen/SparseCore>
#include <sdmesh/cholesky.hpp>
#include <sdmesh/delaunay.hpp>
#include <sdmesh/io.hpp>

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    const sdmesh::TriangleMesh mesh = sdmesh::read_mesh(argv[1]);
    const sdmesh::DelaunayCertificate cert = sdmesh::certify(mesh);
    std::printf("%d faces, %d non-Delaunay edges\n", mesh.num_faces(), cert.non_delaunay_edges);

    Eigen::SparseMatrix<double> A(2, 2);
    A.insert(0, 0) = 2.0;
    A.insert(1, 1) = 4.0;
    A.makeCompressed();
    const Eigen::VectorXd x = sdmesh::CholeskySolver(A).solve(Eigen::VectorXd::Ones(2));
    return mesh.num_faces() > 0 && x[1] == 0.25 ? 0 : 1;
}
