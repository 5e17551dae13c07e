/* make_fclib.c: writes the FCLib test problems of tests/integration/fclib.rs with the
 * FCLib C library itself (fclib_write_local, fclib_write_global,
 * fclib_write_solution), so that `signorini local` is tested on the files
 * the real exporter writes (libhdf5's default format: superblock v0,
 * symbol-table groups).
 *
 * Build (Debian 12: libfclib-dev, libhdf5-dev):
 *   gcc -O2 -Wall -o make_fclib make_fclib.c $(pkg-config --cflags --libs fclib) -lm
 * Normally run by make_fclib.py beside it, which also solves the problems
 * with Siconos and stores its answer as each file's /solution.
 *
 * Modes:
 *   make_fclib problems DIR   writes DIR/fc2d_triplet.hdf5 (2D, triplet
 *                             storage with duplicate entries), fc3d_csc.hdf5
 *                             (3D, compressed columns), fc3d_csr.hdf5 (the
 *                             same 3D problem, compressed rows),
 *                             global2d.hdf5, global3d.hdf5 (global
 *                             problems: a chain of springs, M compressed
 *                             columns and H triplets in 2D, M triplets and H
 *                             compressed columns in 3D), global3d_g.hdf5
 *                             (the 3D one with two equality constraints G,
 *                             b) and mixed.hdf5 (a
 *                             local problem with V and R); prints each
 *                             problem's manufactured solution as one line
 *                             "FILE r... u..." (and "v..." for a global one)
 *   make_fclib solution FILE  reads r then u (W->m numbers each) on stdin
 *                             and stores them with fclib_write_solution
 *   make_fclib global-solution FILE
 *                             reads r, u (H->n numbers each) then v (M->m)
 *                             on stdin into the global problem's /solution
 *   make_fclib merit FILE     prints fclib_merit_local of FILE's /solution
 *                             (3D only in FCLib)
 *
 * The problems are manufactured: W = A Aᵀ + I/2 with A contact-block
 * bidiagonal (so W is block tridiagonal, symmetric positive definite), and a
 * chosen solution (r, u) per contact, open, sticking or slipping, with
 * q = u − W r, so that the answer is known before any solver runs.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <fclib.h>

enum status { OPEN, STICK, SLIP };

/* A deterministic value in [-1, 1] for entry (i, j). */
static double pseudo(int i, int j)
{
  return sin(1.7 * i + 0.37 * j * j + 0.11 * i * j + 0.5);
}

/* W = A Aᵀ + I/2, A with blocks on the contact-block diagonal and
 * subdiagonal; W dense, n × n, row-major. */
static void make_w(int n, int d, double *w)
{
  double *a = calloc((size_t)n * n, sizeof(double));
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
    {
      int bi = i / d, bj = j / d;
      if (bi == bj) a[i * n + j] = (i == j ? 1.0 : 0.3) * (1.0 + 0.5 * pseudo(i, j));
      else if (bi == bj + 1) a[i * n + j] = 0.4 * pseudo(i, j);
    }
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
    {
      double s = (i == j) ? 0.5 : 0.0;
      for (int k = 0; k < n; k++) s += a[i * n + k] * a[j * n + k];
      w[i * n + j] = s;
    }
  free(a);
}

/* A solution of Coulomb's law per contact: r, u (n numbers each). */
static void make_solution(int nc, int d, const enum status *st, const double *mu, double *r, double *u)
{
  for (int c = 0; c < nc; c++)
  {
    double *rc = r + c * d, *uc = u + c * d;
    double rn = 1.0 + 0.5 * c, t[2] = {0.8, -0.6};
    if (d == 2) t[0] = (c % 2) ? -1.0 : 1.0;
    for (int k = 0; k < d; k++) rc[k] = uc[k] = 0.0;
    switch (st[c])
    {
    case OPEN:
      uc[0] = 0.3 + 0.1 * c;
      for (int k = 1; k < d; k++) uc[k] = 0.2 * t[k - 1];
      break;
    case STICK: /* inside the cone: |r_T| = 0.4 μ r_N */
      rc[0] = rn;
      for (int k = 1; k < d; k++) rc[k] = 0.4 * mu[c] * rn * t[k - 1];
      break;
    case SLIP: /* on the cone, opposite the slip u_T */
      rc[0] = rn;
      for (int k = 1; k < d; k++)
      {
        uc[k] = 0.25 * t[k - 1];
        rc[k] = -mu[c] * rn * t[k - 1];
      }
      break;
    }
  }
}

/* q = u − W r. */
static void make_q(int n, const double *w, const double *r, const double *u, double *q)
{
  for (int i = 0; i < n; i++)
  {
    q[i] = u[i];
    for (int j = 0; j < n; j++) q[i] -= w[i * n + j] * r[j];
  }
}

/* A rows × cols matrix (row-major) in triplet form (CSparse's: i rows, p
 * columns), each entry with (i + j) % 4 == 1 split into two (0.25 and 0.75
 * of it): duplicates that FCLib and CSparse sum. */
static struct fclib_matrix *triplet(int rows, int cols, const double *w)
{
  struct fclib_matrix *t = calloc(1, sizeof *t);
  t->p = malloc(2 * rows * cols * sizeof(int));
  t->i = malloc(2 * rows * cols * sizeof(int));
  t->x = malloc(2 * rows * cols * sizeof(double));
  int k = 0;
  for (int j = 0; j < cols; j++)
    for (int i = 0; i < rows; i++)
    {
      double v = w[i * cols + j];
      if (v == 0.0) continue;
      if ((i + j) % 4 == 1)
      {
        t->i[k] = i, t->p[k] = j, t->x[k++] = 0.25 * v;
        v *= 0.75;
      }
      t->i[k] = i, t->p[k] = j, t->x[k++] = v;
    }
  t->m = rows;
  t->n = cols;
  t->nz = t->nzmax = k;
  return t;
}

/* A rows × cols matrix (row-major) compressed by columns (nz = -1) or by
 * rows (nz = -2). */
static struct fclib_matrix *compressed(int rows, int cols, const double *w, int by_rows)
{
  struct fclib_matrix *c = calloc(1, sizeof *c);
  int outer = by_rows ? rows : cols, inner = by_rows ? cols : rows;
  c->p = malloc((outer + 1) * sizeof(int));
  c->i = malloc(rows * cols * sizeof(int));
  c->x = malloc(rows * cols * sizeof(double));
  int k = 0;
  for (int a = 0; a < outer; a++)
  {
    c->p[a] = k;
    for (int b = 0; b < inner; b++)
    {
      double v = by_rows ? w[a * cols + b] : w[b * cols + a];
      if (v == 0.0) continue;
      c->i[k] = b, c->x[k++] = v;
    }
  }
  c->p[outer] = k;
  c->m = rows;
  c->n = cols;
  c->nzmax = k;
  c->nz = by_rows ? -2 : -1;
  return c;
}

static void print_vector(const char *name, int n, const double *v)
{
  printf(" %s", name);
  for (int i = 0; i < n; i++) printf(" %.17g", v[i]);
}

/* DIR/NAME into path (of size bytes), any file there removed. */
static void fresh_path(char *path, size_t size, const char *dir, const char *name)
{
  snprintf(path, size, "%s/%s", dir, name);
  remove(path);
}

/* The problem's name and its manufactured r and u (m numbers each). */
static void print_solution(const char *name, int m, const double *r, const double *u)
{
  printf("%s", name);
  print_vector("r", m, r);
  print_vector("u", m, u);
}

/* Writes one local problem, and prints its manufactured solution. */
static int write_local(const char *dir, const char *name, int nc, int d, const enum status *st,
                       const double *mu, int storage, const char *title)
{
  int n = nc * d;
  double *w = malloc(n * n * sizeof(double)), *q = malloc(n * sizeof(double));
  double *r = malloc(n * sizeof(double)), *u = malloc(n * sizeof(double));
  make_w(n, d, w);
  make_solution(nc, d, st, mu, r, u);
  make_q(n, w, r, u, q);
  struct fclib_info info = {(char *)title, "manufactured: W = A A^T + I/2, q = u - W r", "W SPD"};
  struct fclib_local p = {0};
  p.W = storage == 0 ? triplet(n, n, w) : compressed(n, n, w, storage == 2);
  p.mu = (double *)mu;
  p.q = q;
  p.spacedim = d;
  p.info = &info;
  char path[4096];
  fresh_path(path, sizeof path, dir, name);
  if (!fclib_write_local(&p, path)) return 0;
  print_solution(name, n, r, u);
  printf("\n");
  free(w), free(q), free(r), free(u);
  return 1;
}

/* M of a chain of nn nodes of d DOFs: spring e (stiffness k_e S, S_ab = 1
 * if a = b, else 0.1) between node e - 1 (the ground for e = 0) and node
 * e, and a lumped mass 0.2 + 0.05 i on each DOF i: symmetric positive
 * definite, block tridiagonal; n × n, row-major. */
static void make_m(int nn, int d, double *m)
{
  int n = nn * d;
  memset(m, 0, (size_t)n * n * sizeof(double));
  for (int e = 0; e < nn; e++)
  {
    double k = 1.0 + 0.5 * pseudo(e, 2 * e + 1);
    for (int a = 0; a < d; a++)
      for (int b = 0; b < d; b++)
      {
        double s = k * (a == b ? 1.0 : 0.1);
        int i = e * d + a, j = e * d + b, i0 = i - d, j0 = j - d;
        m[i * n + j] += s;
        if (e == 0) continue;
        m[i0 * n + j0] += s;
        m[i0 * n + j] -= s;
        m[i * n + j0] -= s;
      }
  }
  for (int i = 0; i < n; i++) m[i * n + i] += 0.2 + 0.05 * i;
}

/* The frame of contact c: columns normal, t (2D) or normal, t1, t2 (3D), a
 * rotation (by θ about z, then φ about x in 3D); d × d, row-major. */
static void frame(int c, int d, double *f)
{
  double th = 0.4 * c + 0.3, ph = 0.25 * c - 0.2, ct = cos(th), st = sin(th);
  if (d == 2)
  {
    f[0] = ct, f[1] = -st, f[2] = st, f[3] = ct;
    return;
  }
  double cp = cos(ph), sp = sin(ph);
  double rz[9] = {ct, -st, 0, st, ct, 0, 0, 0, 1}, rx[9] = {1, 0, 0, 0, cp, -sp, 0, sp, cp};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
    {
      f[i * 3 + j] = 0.0;
      for (int k = 0; k < 3; k++) f[i * 3 + j] += rz[i * 3 + k] * rx[k * 3 + j];
    }
}

/* H (n × m, row-major): contact c between chain nodes c + 1 (its frame)
 * and c (-0.3 times its frame). */
static void make_h(int nc, int d, double *h)
{
  int n = (nc + 1) * d, m = nc * d;
  double f[9];
  memset(h, 0, (size_t)n * m * sizeof(double));
  for (int c = 0; c < nc; c++)
  {
    frame(c, d, f);
    for (int a = 0; a < d; a++)
      for (int k = 0; k < d; k++)
      {
        h[((c + 1) * d + a) * m + c * d + k] = f[a * d + k];
        h[(c * d + a) * m + c * d + k] = -0.3 * f[a * d + k];
      }
  }
}

/* G (n × p, row-major) of `p` equality constraints: column k ties DOF
 * 2k + 1 to DOF n − 1 − 2k (weights 1 and −0.5), full column rank. */
static void make_g(int n, int p, double *g)
{
  for (int i = 0; i < n * p; i++) g[i] = 0.0;
  for (int k = 0; k < p; k++)
  {
    g[(2 * k + 1) * p + k] = 1.0;
    g[(n - 1 - 2 * k) * p + k] = -0.5;
  }
}

/* A global problem (M v = H r + G λ + f, Gᵀ v + b = 0, u = Hᵀ v + w) with
 * a manufactured solution: r, u per contact as for the local problems, v
 * and λ chosen, then f = M v − H r − G λ, b = −Gᵀ v and w = u − Hᵀ v. M
 * stored by `m_storage`, H by `h_storage` (0 triplets, 1 columns, 2 rows),
 * G (`p` columns, none when p = 0) by compressed columns. Prints
 * "NAME r... u... v...". */
static int write_global(const char *dir, const char *name, int nc, int d, const enum status *st,
                        const double *mu, int m_storage, int h_storage, int p, const char *title)
{
  int nn = nc + 1, n = nn * d, m = nc * d;
  double *g = malloc((n * p + 1) * sizeof(double)), *lambda = malloc((p + 1) * sizeof(double));
  double *b = malloc((p + 1) * sizeof(double));
  make_g(n, p, g);
  double *mm = malloc(n * n * sizeof(double)), *h = malloc(n * m * sizeof(double));
  double *r = malloc(m * sizeof(double)), *u = malloc(m * sizeof(double)), *w = malloc(m * sizeof(double));
  double *v = malloc(n * sizeof(double)), *f = malloc(n * sizeof(double));
  make_m(nn, d, mm);
  make_h(nc, d, h);
  make_solution(nc, d, st, mu, r, u);
  for (int i = 0; i < n; i++) v[i] = 0.3 * pseudo(i, 5);
  for (int k = 0; k < p; k++) lambda[k] = 0.2 * (k + 1);
  for (int i = 0; i < n; i++)
  {
    f[i] = 0.0;
    for (int j = 0; j < n; j++) f[i] += mm[i * n + j] * v[j];
    for (int j = 0; j < m; j++) f[i] -= h[i * m + j] * r[j];
    for (int k = 0; k < p; k++) f[i] -= g[i * p + k] * lambda[k];
  }
  for (int k = 0; k < p; k++)
  {
    b[k] = 0.0;
    for (int i = 0; i < n; i++) b[k] -= g[i * p + k] * v[i];
  }
  for (int j = 0; j < m; j++)
  {
    w[j] = u[j];
    for (int i = 0; i < n; i++) w[j] -= h[i * m + j] * v[i];
  }
  struct fclib_info info = {(char *)title, "manufactured: chain of springs, f = M v - H r, w = u - H^T v", "M SPD"};
  struct fclib_matrix *ms = m_storage == 0 ? triplet(n, n, mm) : compressed(n, n, mm, m_storage == 2);
  struct fclib_matrix *hs = h_storage == 0 ? triplet(n, m, h) : compressed(n, m, h, h_storage == 2);
  struct fclib_matrix *gs = p > 0 ? compressed(n, p, g, 0) : NULL;
  struct fclib_global problem = {ms, hs, gs, (double *)mu, f, p > 0 ? b : NULL, w, d, &info};
  char path[4096];
  fresh_path(path, sizeof path, dir, name);
  if (!fclib_write_global(&problem, path)) return 0;
  print_solution(name, m, r, u);
  print_vector("v", n, v);
  printf("\n");
  free(mm), free(h), free(r), free(u), free(w), free(v), free(f), free(g), free(lambda), free(b);
  return 1;
}

/* A mixed local problem (with V and R): refused by `local`. */
static int write_mixed(const char *dir)
{
  double w_x[] = {1.0, 1.0}, v_x[] = {1.0}, r_x[] = {2.0}, q[] = {-1.0, 0.5}, s[] = {0.2}, mu[] = {0.3};
  int w_p[] = {0, 1, 2}, w_i[] = {0, 1}, v_p[] = {0, 1}, v_i[] = {0}, r_p[] = {0, 1}, r_i[] = {0};
  struct fclib_matrix wm = {2, 2, 2, w_p, w_i, w_x, -1, NULL};
  struct fclib_matrix vm = {1, 2, 1, v_p, v_i, v_x, -1, NULL};
  struct fclib_matrix rm = {1, 1, 1, r_p, r_i, r_x, -1, NULL};
  struct fclib_local p = {&wm, &vm, &rm, mu, q, s, 2, NULL};
  char path[4096];
  fresh_path(path, sizeof path, dir, "mixed.hdf5");
  return fclib_write_local(&p, path);
}

static int problems(const char *dir)
{
  enum status st2[] = {STICK, SLIP, OPEN, SLIP, STICK};
  double mu2[] = {0.5, 0.3, 0.4, 0.6, 0.2};
  enum status st3[] = {STICK, SLIP, OPEN, SLIP};
  double mu3[] = {0.5, 0.3, 0.4, 0.6};
  return write_local(dir, "fc2d_triplet.hdf5", 5, 2, st2, mu2, 0, "2D: stick, slip, open, slip, stick")
      && write_local(dir, "fc3d_csc.hdf5", 4, 3, st3, mu3, 1, "3D: stick, slip, open, slip")
      && write_local(dir, "fc3d_csr.hdf5", 4, 3, st3, mu3, 2, "3D: stick, slip, open, slip")
      && write_global(dir, "global2d.hdf5", 5, 2, st2, mu2, 1, 0, 0, "global 2D: stick, slip, open, slip, stick")
      && write_global(dir, "global3d.hdf5", 4, 3, st3, mu3, 0, 1, 0, "global 3D: stick, slip, open, slip")
      && write_global(dir, "global3d_g.hdf5", 4, 3, st3, mu3, 0, 1, 2,
                      "global 3D with two equality constraints: stick, slip, open, slip")
      && write_mixed(dir);
}

/* Reads r and u (W->m numbers each) on stdin into FILE's /solution. */
static int solution(const char *path)
{
  struct fclib_local *p = fclib_read_local(path);
  if (!p) return 0;
  int n = p->W->m;
  double *r = malloc(n * sizeof(double)), *u = malloc(n * sizeof(double));
  for (int i = 0; i < 2 * n; i++)
    if (scanf("%lf", i < n ? &r[i] : &u[i - n]) != 1) return 0;
  struct fclib_solution s = {NULL, u, r, NULL};
  int ok = fclib_write_solution(&s, path);
  fclib_delete_local(p);
  free(r), free(u);
  return ok;
}

/* Reads r, u (H->n numbers each) then v (M->m) on stdin into the global
 * problem FILE's /solution. */
static int global_solution(const char *path)
{
  struct fclib_global *p = fclib_read_global(path);
  if (!p) return 0;
  int m = p->H->n, n = p->M->m;
  double *r = malloc(m * sizeof(double)), *u = malloc(m * sizeof(double)), *v = malloc(n * sizeof(double));
  for (int i = 0; i < 2 * m + n; i++)
    if (scanf("%lf", i < m ? &r[i] : i < 2 * m ? &u[i - m] : &v[i - 2 * m]) != 1) return 0;
  struct fclib_solution s = {v, u, r, NULL};
  int ok = fclib_write_solution(&s, path);
  fclib_delete_global(p);
  free(r), free(u), free(v);
  return ok;
}

static int merit(const char *path)
{
  struct fclib_local *p = fclib_read_local(path);
  struct fclib_solution *s = fclib_read_solution(path);
  if (!p || !s) return 0;
  printf("%.3e\n", fclib_merit_local(p, MERIT_1, s));
  return 1;
}

int main(int argc, char **argv)
{
  int ok = 0;
  if (argc == 3 && !strcmp(argv[1], "problems")) ok = problems(argv[2]);
  else if (argc == 3 && !strcmp(argv[1], "solution")) ok = solution(argv[2]);
  else if (argc == 3 && !strcmp(argv[1], "global-solution")) ok = global_solution(argv[2]);
  else if (argc == 3 && !strcmp(argv[1], "merit")) ok = merit(argv[2]);
  else fprintf(stderr, "usage: make_fclib problems DIR | solution FILE | global-solution FILE | merit FILE\n");
  return ok ? 0 : 1;
}
