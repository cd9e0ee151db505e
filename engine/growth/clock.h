/* "clock": a cell of a growing type adds one element every period h of its clock (growth.clock, h), up to
 * max_elements; a full cell's clock runs on. With a proliferative front (Du et al. 2018's wave along x, docs/engine.md)
 * only a cell whose centroid x <= x0 + speed * time (um) grows; ahead of it the cell is quiescent and its clock stands.
 * C99 subset, no include guard: included by clock.cpp (namespace cellrules) and pasted into the OpenCL cell section
 * (growth_laws.cl). Parameters (doubles, growth_law.hpp): (period h, type mask, max_elements, front 0/1, x0 um,
 * speed um/h). A clock of SEMLB_GROWTH_CLOCK_TURNS periods or more is reduced in closed form (births capped by the
 * room left, clock = fmod(clock, period)), never by a loop on its magnitude; below that the loop subtracts one
 * period at a time, so ordinary runs keep their bits. */
#ifndef SEMLB_GROWTH_CLOCK_TURNS
#define SEMLB_GROWTH_CLOCK_TURNS 64.0
#endif
static inline int semlb_growth_clock(int type, int count, const double* centroid, double time, double elapsed,
                                     const double* p, double* clock) {
  if (!(((long)p[1] >> type) & 1)) return 0;
  if (p[3] != 0 && !(centroid[0] <= p[4] + p[5] * time)) return 0;
  int births = 0, max_elements = (int)p[2], room = max_elements - count;
  *clock += elapsed;
  if (*clock < SEMLB_GROWTH_CLOCK_TURNS * p[0]) { /* the usual case: a few periods, one at a time */
    for (; *clock >= p[0]; *clock -= p[0])
      if (births < room) ++births;
    return births;
  }
  /* Many periods at once (a clock from a slower cycle, an edited state): closed form, bounded time; fmod is exact.
   * A clock beyond the doubles (inf after the addition) starts over at 0. */
  births = room > 0 ? room : 0;
  if (*clock / p[0] < (double)births) births = (int)(*clock / p[0]);
  *clock = *clock - *clock == 0 ? fmod(*clock, p[0]) : 0.0;
  return births;
}
