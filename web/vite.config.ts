// Vite builds the front end into web/dist, which `matlas serve` serves from disk.
// `npm run dev` proxies /api to a running `matlas serve` (MATLAS_API, default http://127.0.0.1:8080).
import { defineConfig } from "vite";

export default defineConfig({
  base: "./",
  build: { outDir: "dist", emptyOutDir: true, target: "es2022", chunkSizeWarningLimit: 400 },
  server: {
    proxy: { "/api": process.env.MATLAS_API ?? "http://127.0.0.1:8080" },
  },
});
