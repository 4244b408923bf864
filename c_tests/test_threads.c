/* Many threads query the same shapes at once and get the serial answers; each thread has its own
 * last error message. (POSIX threads; the rest of the file is C99.) */
#define _POSIX_C_SOURCE 200809L
#include "dcol.h"

#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "check.h"

#define THREADS 4
#define QUERIES 200

static dcol_shape *shapes[3];
static dcol_proximity_result expected[QUERIES];

static dcol_pose pose_for(int i) {
  dcol_pose p;
  p.position[0] = 1.0 + 0.01 * i;
  p.position[1] = 0.3 - 0.002 * i;
  p.position[2] = 0.1;
  p.quaternion[0] = 1.0;
  p.quaternion[1] = 0.01 * i;
  p.quaternion[2] = 0.2;
  p.quaternion[3] = -0.1;
  return p;
}

static const dcol_pose origin = {{0, 0, 0}, {1, 0, 0, 0}};

static dcol_status query(int i, dcol_proximity_result *r) {
  dcol_pose p = pose_for(i);
  return dcol_proximity(shapes[i % 3], &origin, shapes[(i + 1) % 3], &p, NULL, r);
}

struct job {
  int id;
  int mismatches;
  int message_ok;
};

static void *worker(void *arg) {
  struct job *job = (struct job *)arg;
  dcol_shape *out = NULL;
  dcol_proximity_result r;
  int i;
  for (i = 0; i < QUERIES; i++) {
    if (query(i, &r) != DCOL_OK || memcmp(&r, &expected[i], sizeof r) != 0) job->mismatches++;
  }
  /* A thread-specific failure: thread k rejects radius -k, and sees only its own message. */
  dcol_shape_new_sphere(-(double)(job->id + 1), &out);
  for (i = 0; i < 50; i++) query(i, &r); /* successes leave the message alone */
  {
    char want[64];
    sprintf(want, "`radius` = -%d:", job->id + 1);
    job->message_ok = strstr(dcol_last_error_message(), want) != NULL;
  }
  return NULL;
}

int main(void) {
  pthread_t threads[THREADS];
  struct job jobs[THREADS];
  int i;

  CHECK(dcol_shape_new_capsule(0.3, 1.0, &shapes[0]) == DCOL_OK);
  CHECK(dcol_shape_new_box(0.4, 0.3, 0.2, &shapes[1]) == DCOL_OK);
  CHECK(dcol_shape_new_cone(0.8, 0.5, &shapes[2]) == DCOL_OK);
  memset(expected, 0, sizeof expected);
  for (i = 0; i < QUERIES; i++) CHECK(query(i, &expected[i]) == DCOL_OK);

  for (i = 0; i < THREADS; i++) {
    jobs[i].id = i;
    jobs[i].mismatches = 0;
    jobs[i].message_ok = 0;
    CHECK(pthread_create(&threads[i], NULL, worker, &jobs[i]) == 0);
  }
  for (i = 0; i < THREADS; i++) {
    CHECK(pthread_join(threads[i], NULL) == 0);
    CHECK_MSG(jobs[i].mismatches == 0, "thread %d: %d results differ", i, jobs[i].mismatches);
    CHECK_MSG(jobs[i].message_ok, "thread %d saw another thread's message", i);
  }
  /* The main thread has not failed at all. */
  CHECK(strcmp(dcol_last_error_message(), "") == 0);

  for (i = 0; i < 3; i++) dcol_shape_free(shapes[i]);
  return check_summary("test_threads");
}
