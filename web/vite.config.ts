// Vite builds the front end into web/dist, which `matlas serve` serves from disk.
// The reference docs become pages under dist/docs (docs-pages.ts), linked from the help dialog.
// `npm run dev` proxies /api to a running `matlas serve` (MATLAS_API, default http://127.0.0.1:8080).
import { defineConfig } from "vite";
import { docsPages } from "./docs-pages";

export default defineConfig({
  base: "./",
  plugins: [docsPages()],
  build: { outDir: "dist", emptyOutDir: true, target: "es2022", chunkSizeWarningLimit: 400 },
  server: {
    proxy: { "/api": process.env.MATLAS_API ?? "http://127.0.0.1:8080" },
  },
});
