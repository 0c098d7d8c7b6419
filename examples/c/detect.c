/* Boundary particles from C: the shortest use of the C API, checked against the CLI.
 *
 *   cc detect.c -I crates/boundary-capi/include -L target/debug -lboundary_capi -o detect
 *   boundary detect frame.csv --radius 0.05 --output labels.csv   # the reference labels
 *   ./detect labels.csv 0.05 exact ""
 *
 * Reads a CSV written by `boundary detect --output` (columns x, y[, z], boundary, ...),
 * labels its particles with `boundary_detect` and, for a simulation loop, with a reusable
 * `boundary_detector` handle, and compares both with the file's `boundary` column. Prints one
 * line `n=... dim=... boundary=... mismatches=...`; exits 0 iff nothing differs.
 *
 * A radius per particle: when the file has a `radius` column (as `boundary detect
 * frame.csv --radius-attribute radius --radius-scale 0.05 --output labels.csv` writes it
 * back), R is the scale and particle i gets r_i = R * radius_i, through
 * `boundary_detect_radii` and `boundary_detector_detect_radii` (whose NULL radii mean one
 * radius R for all).
 *
 * Walls: a solver's fixed boundary particles cover its fluid but get no label. Set once on
 * a handle (`boundary_detector_set_walls`), they count in every detection by it: with the
 * file's second half as walls, the first half gets the labels of the whole file.
 *
 * Time steps: with method exact, a `boundary_tracker` labels the same particles step after
 * step, recomputing only those whose label may have changed.
 * `cargo xtask test` builds and runs it on the public data. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "boundary.h"

#define MAX_LINE 4096

/* Index of `name` among the comma-separated header fields, or -1. */
static int column(const char *header, const char *name) {
    char copy[MAX_LINE];
    strncpy(copy, header, sizeof copy - 1);
    copy[sizeof copy - 1] = '\0';
    copy[strcspn(copy, "\r\n")] = '\0';
    int k = 0;
    for (char *field = strtok(copy, ","); field; field = strtok(NULL, ","), ++k)
        if (strcmp(field, name) == 0) return k;
    return -1;
}

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: %s LABELS.csv R METHOD [PARAMS]\n", argv[0]);
        return 2;
    }
    const double r = strtod(argv[2], NULL);
    const char *method = argv[3];
    const char *params = argc > 4 ? argv[4] : "";
    FILE *f = fopen(argv[1], "r");
    if (!f) {
        perror(argv[1]);
        return 1;
    }
    char line[MAX_LINE];
    if (!fgets(line, sizeof line, f)) {
        fprintf(stderr, "%s: empty file\n", argv[1]);
        return 1;
    }
    const int cx = column(line, "x"), cy = column(line, "y"), cz = column(line, "z");
    const int cb = column(line, "boundary");
    const int cr = column(line, "radius"); /* optional: a radius per particle */
    if (cx < 0 || cy < 0 || cb < 0) {
        fprintf(stderr, "%s: needs columns x, y and boundary\n", argv[1]);
        return 1;
    }
    const int dim = cz >= 0 ? 3 : 2;
    size_t n = 0, cap = 1024;
    double *xyz = malloc(cap * 3 * sizeof *xyz);
    double *radii = malloc(cap * sizeof *radii);
    uint8_t *expected = malloc(cap);
    while (xyz && radii && expected && fgets(line, sizeof line, f)) {
        if (n == cap) {
            cap *= 2;
            xyz = realloc(xyz, cap * 3 * sizeof *xyz);
            radii = realloc(radii, cap * sizeof *radii);
            expected = realloc(expected, cap);
            if (!xyz || !radii || !expected) break;
        }
        int k = 0;
        for (char *field = strtok(line, ",\r\n"); field; field = strtok(NULL, ",\r\n"), ++k) {
            if (k == cx) xyz[n * dim] = strtod(field, NULL);
            if (k == cy) xyz[n * dim + 1] = strtod(field, NULL);
            if (k == cz) xyz[n * dim + 2] = strtod(field, NULL);
            if (k == cb) expected[n] = (uint8_t)atoi(field);
            if (k == cr) radii[n] = strtod(field, NULL);
        }
        ++n;
    }
    fclose(f);
    if (!xyz || !radii || !expected) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    /* NULL: one radius r for every particle. */
    const double *particle_radii = cr >= 0 ? radii : NULL;

    /* One call: method and parameters parsed on each call. */
    uint8_t *labels = malloc(n ? n : 1);
    char err[256];
    const int code = particle_radii
        ? boundary_detect_radii(xyz, n, dim, particle_radii, r, method, params, labels, err,
                                sizeof err)
        : boundary_detect(xyz, n, dim, r, method, params, labels, err, sizeof err);
    if (code != BOUNDARY_OK) {
        fprintf(stderr, "boundary_detect: error %d: %s\n", code, err);
        return 1;
    }

    /* A handle for per-step use: created once, used every time step. */
    boundary_detector *detector = boundary_detector_new(method, params, err, sizeof err);
    if (!detector) {
        fprintf(stderr, "boundary_detector_new: %s\n", err);
        return 1;
    }
    uint8_t *step_labels = malloc(n ? n : 1);
    size_t mismatches = 0, count = 0;
    for (int step = 0; step < 2; ++step) {
        int code = boundary_detector_detect_radii(detector, xyz, n, dim, particle_radii, r,
                                                  step_labels, NULL, err, sizeof err);
        if (code != BOUNDARY_OK) {
            fprintf(stderr, "boundary_detector_detect: error %d: %s\n", code, err);
            return 1;
        }
        for (size_t i = 0; i < n; ++i) mismatches += step_labels[i] != expected[i];
    }

    /* The second half of the particles as walls, set once: the first half's labels are those
     * of the whole set. */
    const size_t half = n / 2;
    if (boundary_detector_set_walls(detector, xyz + half * dim, n - half, dim,
                                    particle_radii ? radii + half : NULL, err,
                                    sizeof err) != BOUNDARY_OK) {
        fprintf(stderr, "boundary_detector_set_walls: %s\n", err);
        return 1;
    }
    if (boundary_detector_detect_radii(detector, xyz, half, dim, particle_radii, r, step_labels,
                                       NULL, err, sizeof err) != BOUNDARY_OK) {
        fprintf(stderr, "boundary_detector_detect (walls): %s\n", err);
        return 1;
    }
    for (size_t i = 0; i < half; ++i) mismatches += step_labels[i] != expected[i];
    boundary_detector_free(detector);

    /* The exact labels every time step, incrementally: a tracker recomputes only the
     * particles whose label may have changed. Unmoved particles: nothing to recompute. */
    if (strcmp(method, "exact") == 0 && params[0] == '\0' && !particle_radii) {
        boundary_tracker *tracker = boundary_tracker_new(r, 0, err, sizeof err);
        if (!tracker) {
            fprintf(stderr, "boundary_tracker_new: %s\n", err);
            return 1;
        }
        size_t recomputed = 0;
        for (int step = 0; step < 2; ++step) {
            if (boundary_tracker_update(tracker, xyz, n, dim, step_labels, &recomputed, err,
                                        sizeof err) != BOUNDARY_OK) {
                fprintf(stderr, "boundary_tracker_update: %s\n", err);
                return 1;
            }
            for (size_t i = 0; i < n; ++i) mismatches += step_labels[i] != expected[i];
        }
        if (recomputed != 0) {
            fprintf(stderr, "boundary_tracker_update: %zu recomputed without a move\n",
                    recomputed);
            ++mismatches;
        }
        boundary_tracker_free(tracker);
    }

    for (size_t i = 0; i < n; ++i) {
        mismatches += labels[i] != expected[i];
        count += labels[i];
    }
    printf("n=%zu dim=%d boundary=%zu mismatches=%zu (boundary %s, %s%s)\n", n, dim, count,
           mismatches, boundary_version(), method,
           particle_radii ? ", a radius per particle" : "");
    free(xyz);
    free(radii);
    free(expected);
    free(labels);
    free(step_labels);
    return mismatches == 0 ? 0 : 1;
}
