/* Symmetric banded LDL^T factorisation and solve (no pivoting).
 *
 * The effective stiffness M / (beta dt^2) + gamma / (beta dt) C + K_T of a pounding scene is
 * symmetric and, with its mass term, positive definite; DOFs are numbered by reverse
 * Cuthill-McKee so that the half-bandwidth stays small (one building per row of floors: about
 * the number of buildings), and the cost per solve is O(n bw^2) instead of O(n^3).
 *
 * Storage: band[i * (bw + 1) + d] holds K[i, i - d] for d = 0..bw (lower band, diagonal
 * first).
 */

#define BAND(i, d) band[(i) * (bw + 1) + (d)]

/* Overwrite band with L (unit lower, off-diagonals) and D (diagonal); -1 when every pivot is
 * positive, else the row whose pivot is not (the effective stiffness lost definiteness). */
static int64_t ldl_factor(double *band, int64_t n, int64_t bw)
{
    int64_t i, j, k;
    for (j = 0; j < n; j++) {
        double d = BAND(j, 0);
        for (k = imax(0, j - bw); k < j; k++) {
            double ljk = BAND(j, j - k);
            d -= ljk * ljk * BAND(k, 0);
        }
        if (!(d > 0.0))
            return j;
        BAND(j, 0) = d;
        for (i = j + 1; i < imin(n, j + bw + 1); i++) {
            double s = BAND(i, i - j);
            for (k = imax(0, i - bw); k < j; k++)
                s -= BAND(i, i - k) * BAND(j, j - k) * BAND(k, 0);
            BAND(i, i - j) = s / d;
        }
    }
    return -1;
}

/* ldl_solve for a band of bw, a constant where a case of ldl_solve inlines it: a row with bw
 * terms on its side is a loop of bw, which the compiler unrolls (the generic loop's bounds,
 * max(0, i - bw) and min(n, i + bw + 1), made a solve's loops mostly overhead: about 6 % of a
 * step of the paper's pair, bandwidth 2); the first and last bw rows (fewer terms) loop as
 * before. Each x[i] takes its terms in the same order (k ascending) and is divided by its
 * pivot before its back-substitution's terms, as before: the same bits. */
static PFRAME_INLINE void ldl_solve_band(const double *band, int64_t n, int64_t bw, double *x)
{
    const int64_t head = imin(n, bw), tail = imax(0, n - bw);
    int64_t i, k, d;
    for (i = 0; i < head; i++) {
        double s = x[i];
        for (k = 0; k < i; k++)
            s -= BAND(i, i - k) * x[k];
        x[i] = s;
    }
    for (i = head; i < n; i++) {
        const double *row = band + i * (bw + 1);
        double s = x[i];
        for (d = bw; d >= 1; d--)
            s -= row[d] * x[i - d];
        x[i] = s;
    }
    for (i = n - 1; i >= tail; i--) {
        double s = x[i] / BAND(i, 0);
        for (k = i + 1; k < n; k++)
            s -= BAND(k, k - i) * x[k];
        x[i] = s;
    }
    for (i = tail - 1; i >= 0; i--) {
        double s = x[i] / BAND(i, 0);
        for (d = 1; d <= bw; d++)
            s -= BAND(i + d, d) * x[i + d];
        x[i] = s;
    }
}

/* Solve in place with a factor from ldl_factor: the narrow bands of planar scenes (about one
 * per building in a row) each a case of their own. */
static void ldl_solve(const double *band, int64_t n, int64_t bw, double *x)
{
    switch (bw) {
    case 1:
        ldl_solve_band(band, n, 1, x);
        break;
    case 2:
        ldl_solve_band(band, n, 2, x);
        break;
    case 3:
        ldl_solve_band(band, n, 3, x);
        break;
    case 4:
        ldl_solve_band(band, n, 4, x);
        break;
    default:
        ldl_solve_band(band, n, bw, x);
    }
}

#undef BAND
