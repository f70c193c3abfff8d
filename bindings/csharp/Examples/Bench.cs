// What calls cost through the binding: a trivial call, and a body's vertices after a shape change
// (what an engine does per frame), as medians of 5 runs. Compare with tests/bindings/bench.c.
// usage: mono Bench.exe
using System;
using System.Diagnostics;
using Sscape;

static class Bench
{
    static double Median(Action<int> f, int repeats)
    {
        double[] times = new double[5];
        for (int r = 0; r < 5; ++r)
        {
            Stopwatch watch = Stopwatch.StartNew();
            for (int i = 0; i < repeats; ++i) f(i);
            times[r] = watch.Elapsed.TotalMilliseconds * 1e6 / repeats;
        }
        Array.Sort(times);
        return times[2];
    }

    static void Main()
    {
        using (Model model = Model.LoadDefault())
        using (Body body = model.CreateBody())
        {
            int k = model.ShapeCount;
            float[] shapes = model.SampleShapes(16, 1);
            float[][] each = new float[16][];
            for (int b = 0; b < 16; ++b) { each[b] = new float[k]; Array.Copy(shapes, b * k, each[b], 0, k); }
            float[] vertices = new float[model.VertexCount * 3];
            long sink = 0;
            double call = Median(i => sink += model.VertexCount, 100000);
            double frame = Median(i => { body.Shape = each[i % 16]; body.GetVertices(vertices); }, 300);
            Console.WriteLine("csharp: call {0:F0} ns, shape+vertices {1:F1} us ({2})", call, frame / 1000, sink % 2);
        }
    }
}
