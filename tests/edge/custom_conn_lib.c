/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * A connect-type CUSTOM connection library for the tests, in C against src/edge/custom/
 * nns_edge_abi.h and linked to our libnnstreamer-edge (as an upstream-built one is linked to
 * nnstreamer-edge's). Transport: UDP datagrams on 127.0.0.1 carrying serialized edge data
 * (nns_edge_data_serialize); the subscriber binds DEST_PORT, the publisher sends to DEST_PORT.
 * Every call is appended to the file named by $NNS_TEST_CUSTOM_TRACE (one line each) so the
 * test can check the order nnstreamer-edge's callers use. Built with -DNNS_TEST_NO_START it
 * leaves nns_edge_custom_start NULL (a broken library).
 */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <unistd.h>

#include "edge/custom/nns_edge_abi.h"

typedef struct {
  int fd;
  int port;
  int connected;
  int running;
  int is_pub; /* got HOST: only publishers are given their own address */
  pthread_t thread;
  nns_edge_event_cb cb;
  void *user_data;
} conn_s;

static void trace(const char *fmt, const char *a, const char *b) {
  const char *path = getenv("NNS_TEST_CUSTOM_TRACE");
  FILE *f;
  if (!path || !(f = fopen(path, "a"))) return;
  fprintf(f, fmt, a ? a : "", b ? b : "");
  fputc('\n', f);
  fclose(f);
}

static const char *describe(void) {
  return "udp test connection";
}

static int create(void **priv) {
  conn_s *c = calloc(1, sizeof(conn_s));
  if (!c) return NNS_EDGE_ERROR_OUT_OF_MEMORY;
  c->fd = -1;
  *priv = c;
  trace("create", NULL, NULL);
  return NNS_EDGE_ERROR_NONE;
}

static int close_conn(void *priv) {
  trace("close", NULL, NULL);
  free(priv);
  return NNS_EDGE_ERROR_NONE;
}

static int set_event_cb(void *priv, nns_edge_event_cb cb, void *user_data) {
  conn_s *c = priv;
  c->cb = cb;
  c->user_data = user_data;
  trace("set_event_cb", NULL, NULL);
  return NNS_EDGE_ERROR_NONE;
}

static int set_info(void *priv, const char *key, const char *value) {
  conn_s *c = priv;
  trace("set_info %s=%s", key, value);
  if (strcasecmp(key, "DEST_PORT") == 0) c->port = atoi(value);
  if (strcasecmp(key, "HOST") == 0) c->is_pub = 1;
  return NNS_EDGE_ERROR_NONE;
}

static int get_info(void *priv, const char *key, char **value) {
  (void)priv;
  (void)key;
  (void)value;
  return NNS_EDGE_ERROR_NOT_SUPPORTED;
}

static int start(void *priv) {
  conn_s *c = priv;
  c->fd = socket(AF_INET, SOCK_DGRAM, 0);
  trace("start", NULL, NULL);
  return c->fd >= 0 ? NNS_EDGE_ERROR_NONE : NNS_EDGE_ERROR_IO;
}

static void *receive_loop(void *priv) {
  conn_s *c = priv;
  static unsigned char buf[65536];
  while (c->running) {
    ssize_t n = recv(c->fd, buf, sizeof buf, 0);
    if (n <= 0) continue;
    if (n == 3 && memcmp(buf, "bye", 3) == 0) {
      nns_edge_event_invoke_callback(c->cb, c->user_data, NNS_EDGE_EVENT_CONNECTION_CLOSED, NULL, 0,
                                     NULL);
      continue;
    }
    nns_edge_data_h d;
    if (nns_edge_data_create(&d) != NNS_EDGE_ERROR_NONE) continue;
    if (nns_edge_data_deserialize(d, buf, (nns_size_t)n) == NNS_EDGE_ERROR_NONE)
      nns_edge_event_invoke_callback(c->cb, c->user_data, NNS_EDGE_EVENT_NEW_DATA_RECEIVED, d,
                                     sizeof(nns_edge_data_h), NULL);
    nns_edge_data_destroy(d);
  }
  return NULL;
}

/* Subscriber: bind DEST_PORT and receive. */
static int connect_conn(void *priv) {
  conn_s *c = priv;
  struct sockaddr_in a;
  struct timeval tv = {0, 100000};
  trace("connect", NULL, NULL);
  memset(&a, 0, sizeof a);
  a.sin_family = AF_INET;
  a.sin_port = htons((unsigned short)c->port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (bind(c->fd, (struct sockaddr *)&a, sizeof a) != 0) return NNS_EDGE_ERROR_CONNECTION_FAILURE;
  setsockopt(c->fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  c->running = 1;
  c->connected = 1;
  pthread_create(&c->thread, NULL, receive_loop, c);
  return NNS_EDGE_ERROR_NONE;
}

static int is_connected(void *priv) {
  conn_s *c = priv;
  /* A publisher is "connected" once started (datagrams need no peer). */
  return (c->connected || (c->is_pub && c->fd >= 0 && c->port > 0))
             ? NNS_EDGE_ERROR_NONE
             : NNS_EDGE_ERROR_CONNECTION_FAILURE;
}

static int send_data(void *priv, nns_edge_data_h data_h) {
  conn_s *c = priv;
  void *bytes = NULL;
  nns_size_t len = 0;
  struct sockaddr_in a;
  char n[32];
  unsigned int count = 0;
  nns_edge_data_get_count(data_h, &count);
  snprintf(n, sizeof n, "%u", count);
  trace("send_data %s memories", n, NULL);
  if (nns_edge_data_serialize(data_h, &bytes, &len) != NNS_EDGE_ERROR_NONE)
    return NNS_EDGE_ERROR_IO;
  memset(&a, 0, sizeof a);
  a.sin_family = AF_INET;
  a.sin_port = htons((unsigned short)c->port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  sendto(c->fd, bytes, len, 0, (struct sockaddr *)&a, sizeof a);
  free(bytes);
  return NNS_EDGE_ERROR_NONE;
}

static int stop(void *priv) {
  conn_s *c = priv;
  trace("stop", NULL, NULL);
  if (c->running) {
    c->running = 0;
    pthread_join(c->thread, NULL);
  }
  if (c->fd >= 0) close(c->fd);
  c->fd = -1;
  c->connected = 0;
  return NNS_EDGE_ERROR_NONE;
}

static int disconnect(void *priv) {
  (void)priv;
  trace("disconnect", NULL, NULL);
  return NNS_EDGE_ERROR_NONE;
}

static int not_supported(void *priv) {
  (void)priv;
  return NNS_EDGE_ERROR_NOT_SUPPORTED;
}

static const nns_edge_custom_s instance = {
    describe,      create,       close_conn,
#ifdef NNS_TEST_NO_START
    NULL,
#else
    start,
#endif
    stop,          connect_conn, disconnect, not_supported, is_connected, not_supported,
    not_supported, set_event_cb, send_data,  set_info,      get_info};

const nns_edge_custom_s *nns_edge_custom_get_instance(void) {
  return &instance;
}
