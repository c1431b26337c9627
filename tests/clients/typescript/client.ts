// A short script against the client generated from docs/openapi.json (openapi-typescript + openapi-fetch), as a
// researcher would write it; tests/clients/typescript_client_test.py type-checks it with `tsc --strict` (never run).
import createClient from "openapi-fetch";
import type { paths } from "./api";

const client = createClient<paths>({ baseUrl: "http://127.0.0.1:8080" });

export async function tour(): Promise<void> {
  // A partial spec: every field the server defaults is left out.
  const submitted = await client.POST("/v1/jobs", {
    body: { experiment: "crystal_compression", crystal: { grains_x: 2, rows_z: 3, layers_y: 2 } },
    params: { query: { priority: 0 } },
  });
  if (submitted.error) throw new Error(`${submitted.error.error.code}: ${submitted.error.error.message}`);
  // 201 queued, or 200 when reused (?reuse=true) or a dry run: told apart by `reused` and `dry_run`.
  if ("dry_run" in submitted.data) throw new Error("not a dry run");
  const id: number = submitted.data.id;

  const job = await client.GET("/v1/jobs/{id}", { params: { path: { id } } });
  if (job.error) throw new Error(job.error.error.message);
  const status: string = job.data.status;
  const progress: number = job.data.progress;
  const created: number = job.data.created_ms;
  const steps: number | undefined = job.data.summary?.steps;
  const version: string | undefined = job.data.summary?.engine_version;
  const firstYield: unknown = job.data.summary?.["first_yield"];  // an experiment's own group

  const dry = await client.POST("/v1/jobs", { body: { experiment: "two_cube_sliding" }, params: { query: { dry_run: true } } });
  if (dry.data && "dry_run" in dry.data) console.log(dry.data.expected_seconds, dry.data.yield_estimate);

  const curve = await client.GET("/v1/jobs/{id}/curve", { params: { path: { id } } });
  if (curve.data && typeof curve.data !== "string") console.log(curve.data.columns.length, curve.data["strain"]);

  const sweep = await client.POST("/v1/sweeps", {
    body: { spec: { experiment: "crystal_compression" }, vary: { "loading.confining_pressure": [10e3, 30e3] } },
  });
  if (sweep.data) {
    const jobs: number[] = sweep.data.jobs;
    const one = await client.GET("/v1/sweeps/{id}", { params: { path: { id: sweep.data.id } } });
    if (one.data) {
      for (const j of one.data.jobs) console.log(j.id, j.status, j.progress, j.values);
      console.log(one.data.counts, one.data.label, one.data.vary, jobs.length);
    }
  }
  const list = await client.GET("/v1/jobs", { params: { query: { status: "queued", limit: 10 } } });
  if (list.data) for (const j of list.data.jobs) console.log(j.id, j.status, j.label);
  const sweeps = await client.GET("/v1/sweeps", {});
  if (sweeps.data) for (const s of sweeps.data.sweeps) console.log(s.id, s.mode, s.created_ms);
  console.log(status, progress, created, steps, version, firstYield);
}
