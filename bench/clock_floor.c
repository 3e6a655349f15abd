/* This machine's timing floor, apart from pacer: a fixed workload (300 dependent
 * multiply-adds) timed a million times between two reads of the thread's CPU clock, as
 * benches/pickplace.rs times a module cycle. Its tail is what interrupts and the hypervisor
 * charge to the running thread, which no code under test can lower.
 *
 *   cc -O2 bench/clock_floor.c -o /tmp/clock_floor && /tmp/clock_floor
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now_us(void) {
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec * 1e6 + t.tv_nsec / 1e3;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(void) {
    const int n = 1000000;
    double *d = malloc(n * sizeof *d);
    if (!d) return 1;
    volatile double s = 0;
    for (int i = 0; i < n; i++) {
        double a = now_us();
        for (int k = 0; k < 300; k++) s += k * 0.5;
        d[i] = now_us() - a;
    }
    qsort(d, n, sizeof *d, cmp);
    double mean = 0;
    int over10 = 0;
    for (int i = 0; i < n; i++) {
        mean += d[i];
        over10 += d[i] > 10.0;
    }
    printf("fixed workload, thread CPU time: mean %.2f µs, p50 %.2f µs, p99 %.2f µs, "
           "p99.9 %.2f µs, worst %.2f µs; %d of %d over 10 µs\n",
           mean / n, d[n / 2], d[n * 99 / 100], d[n * 999 / 1000], d[n - 1], over10, n);
    free(d);
    return 0;
}
