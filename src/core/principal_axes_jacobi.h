// The cyclic Jacobi rotations of principalAxis (bricks.cpp), written once for
// any vector of lanes: the same operations in the same order, each exactly
// rounded in every lane, applied only in the lanes still sweeping, so each
// lane gives principalAxis's bits. Private to principal_axes*.cpp: each
// includes it with its own lane type, compiled for its own instruction set.
#pragma once

namespace yv::jacobi {

/// Unnormalised eigenvector of the largest diagonal entry of each lane's
/// tensor, picked as principalAxis picks it. L is a lane type: V (a
/// vector of L::width doubles) and its arithmetic, comparisons and masks.
template <class L>
void largestEigenvectors(const double* const (&t)[L::width], double (&axes)[L::width][3]) {
    using V = typename L::V;
    const auto gather = [&](int i) {
        double lanes[L::width];
        for (int l = 0; l < L::width; ++l) lanes[l] = t[l][i];
        return L::load(lanes);
    };
    const V zero = L::set1(0.0), one = L::set1(1.0);
    V a[3][3] = {{gather(0), gather(3), gather(4)}, {gather(3), gather(1), gather(5)}, {gather(4), gather(5), gather(2)}};
    V v[3][3] = {{one, zero, zero}, {zero, one, zero}, {zero, zero, one}};
    V live = L::cmpeq(zero, zero);
    for (int sweep = 0; sweep < 12; ++sweep) {
        const V off = L::add(L::add(L::mul(a[0][1], a[0][1]), L::mul(a[0][2], a[0][2])), L::mul(a[1][2], a[1][2]));
        const V diag = L::add(L::add(L::mul(a[0][0], a[0][0]), L::mul(a[1][1], a[1][1])), L::mul(a[2][2], a[2][2]));
        const V converged = L::bitOr(L::cmple(off, L::mul(L::set1(1e-30), diag)), L::cmpeq(off, zero));
        live = L::andNot(converged, live);
        if (L::none(live)) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                const V turn = L::andNot(L::cmpeq(a[p][q], zero), live);
                if (L::none(turn)) continue;
                const V theta = L::div(L::sub(a[q][q], a[p][p]), L::mul(L::set1(2.0), a[p][q]));
                const V sign = L::select(L::cmpge(theta, zero), one, L::set1(-1.0));
                const V magnitude = L::andNot(L::set1(-0.0), theta);
                const V tt = L::div(sign, L::add(magnitude, L::sqrt(L::add(L::mul(theta, theta), one))));
                const V c = L::div(one, L::sqrt(L::add(L::mul(tt, tt), one))), s = L::mul(tt, c);
                for (int k = 0; k < 3; ++k) { // A <- A J
                    const V akp = a[k][p], akq = a[k][q];
                    a[k][p] = L::select(turn, L::sub(L::mul(c, akp), L::mul(s, akq)), akp);
                    a[k][q] = L::select(turn, L::add(L::mul(s, akp), L::mul(c, akq)), akq);
                }
                for (int k = 0; k < 3; ++k) { // A <- J^T A
                    const V apk = a[p][k], aqk = a[q][k];
                    a[p][k] = L::select(turn, L::sub(L::mul(c, apk), L::mul(s, aqk)), apk);
                    a[q][k] = L::select(turn, L::add(L::mul(s, apk), L::mul(c, aqk)), aqk);
                }
                for (int k = 0; k < 3; ++k) { // V <- V J
                    const V vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = L::select(turn, L::sub(L::mul(c, vkp), L::mul(s, vkq)), vkp);
                    v[k][q] = L::select(turn, L::add(L::mul(s, vkp), L::mul(c, vkq)), vkq);
                }
            }
    }
    double diagonal[3][L::width], vectors[3][3][L::width];
    for (int i = 0; i < 3; ++i) {
        L::store(diagonal[i], a[i][i]);
        for (int j = 0; j < 3; ++j) L::store(vectors[i][j], v[i][j]);
    }
    for (int l = 0; l < L::width; ++l) {
        int best = 0;
        for (int i = 1; i < 3; ++i)
            if (diagonal[i][l] > diagonal[best][l]) best = i;
        for (int i = 0; i < 3; ++i) axes[l][i] = vectors[i][best][l];
    }
}

/// Eight lanes with AVX (principal_axes_avx.cpp, built with -mavx): only
/// call where cpuHasAvx() (core/cpu_features.h).
void largestEigenvectorsAvx(const double* const (&t)[8], double (&axes)[8][3]);

} // namespace yv::jacobi
