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

/* Solve in place with a factor from ldl_factor. */
static void ldl_solve(const double *band, int64_t n, int64_t bw, double *x)
{
    int64_t i, k;
    for (i = 0; i < n; i++) {
        double s = x[i];
        for (k = imax(0, i - bw); k < i; k++)
            s -= BAND(i, i - k) * x[k];
        x[i] = s;
    }
    for (i = 0; i < n; i++)
        x[i] /= BAND(i, 0);
    for (i = n - 1; i >= 0; i--) {
        double s = x[i];
        for (k = i + 1; k < imin(n, i + bw + 1); k++)
            s -= BAND(k, k - i) * x[k];
        x[i] = s;
    }
}

#undef BAND
